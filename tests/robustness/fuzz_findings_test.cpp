// Every input the fuzzers ever found a problem with (tests/data/fuzz/TARGET/), replayed through the
// same loader in the same surroundings as its fuzz target (tests/fuzz/fuzz_TARGET.cpp), so the
// default suite (and its sanitizer build) keeps each fix.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/image.h"
#include "env/environment.h"
#include "robustness_support.h"
#include "sample_inputs.h"
#include "scene/gltf.h"
#include "scene/scene.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> findings(const std::string& target) {
    std::vector<fs::path> files;
    const fs::path folder = fs::path(ENVSHADOW_SOURCE_DIR) / "tests/data/fuzz" / target;
    if (fs::is_directory(folder))
        for (const auto& entry : fs::directory_iterator(folder))
            if (entry.is_regular_file()) files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    return files;
}

void expect_sound_mesh(const Mesh& mesh) {
    ASSERT_FALSE(mesh.indices.empty());
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
    for (const std::uint32_t i : mesh.indices) ASSERT_LT(i, mesh.positions.size());
}

TEST(FuzzFindings, ThereAreFindingsToReplay) {
    std::size_t count = 0;
    for (const char* target : {"gltf", "scene", "exr", "hdr"}) count += findings(target).size();
    EXPECT_GT(count, 0u);
}

TEST(FuzzFindings, GltfInputsLoadSoundlyOrFailCleanly) {
    const fs::path dir = test::fresh_folder();
    std::vector<float> values(64);  // the harness's buffer.bin
    for (std::size_t i = 0; i < values.size(); ++i) values[i] = float(i % 8);
    std::vector<std::uint8_t> bin(values.size() * 4);
    std::memcpy(bin.data(), values.data(), bin.size());
    test::write_bytes(dir / "buffer.bin", bin);
    for (const fs::path& finding : findings("gltf")) {
        const auto bytes = test::read_bytes(finding);
        const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
        const fs::path file = dir / (binary ? "input.glb" : "input.gltf");
        test::write_bytes(file, bytes);
        test::loads_or_fails_cleanly(
            file,
            [&] {
                for (const GltfPart& part : load_gltf(file).parts) expect_sound_mesh(*part.mesh);
            },
            finding.string());
    }
}

TEST(FuzzFindings, SceneInputsLoadSoundlyOrFailCleanly) {
    const fs::path dir = test::fresh_folder();
    test::write_sample_glb(dir / "box.glb");
    test::write_sample_hdr(dir / "sky.hdr", 16, 8, true);
    for (const fs::path& finding : findings("scene")) {
        const fs::path file = dir / "scene.json";
        test::write_bytes(file, test::read_bytes(finding));
        test::loads_or_fails_cleanly(
            file,
            [&] {
                for (const Object& object : load_scene(file).objects) expect_sound_mesh(*object.mesh);
            },
            finding.string());
    }
}

// As fuzz_exr and fuzz_hdr: load_environment (the reader, then the map's shape and texel checks).
void expect_sound_map(const EnvironmentMap& map) {
    ASSERT_GE(map.width, 2);
    ASSERT_EQ(map.width, 2 * map.height);
    ASSERT_LE(map.width, kMaxEnvironmentWidth);
    ASSERT_EQ(map.texels.size(), std::size_t(map.width) * std::size_t(map.height));
    for (const glm::vec3& t : map.texels)
        for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(t[c]) && t[c] >= 0.0f) << t[c];
}

TEST(FuzzFindings, MapInputsLoadSoundlyOrFailCleanly) {
    const fs::path dir = test::fresh_folder();
    for (const char* format : {"exr", "hdr"})
        for (const fs::path& finding : findings(format)) {
            const fs::path file = dir / (std::string("input.") + format);
            test::write_bytes(file, test::read_bytes(finding));
            test::loads_or_fails_cleanly(
                file, [&] { expect_sound_map(load_environment(file.string())); }, finding.string());
        }
}

TEST(OneLineMessages, ControlCharactersFromInputsAreEscaped) {
    // A JSON key or a URI can hold any character; the message quoting it must stay one line.
    const InputError error(std::string("scene.json: objects.a\nb\r\tc\x01: unknown key"));
    EXPECT_STREQ(error.what(), "scene.json: objects.a\\nb\\r\\tc\\x01: unknown key");
    const UsageError usage(std::string("--method: unknown method \"x\ny\""));
    EXPECT_STREQ(usage.what(), "--method: unknown method \"x\\ny\"");
}

}  // namespace
}  // namespace envshadow
