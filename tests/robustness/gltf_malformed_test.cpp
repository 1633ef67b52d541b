// glTF / GLB inputs broken in ways tests/scene does not cover: every truncation, random bit flips,
// special files behind URIs (a FIFO must not hang the loader), hierarchies and JSON deep enough to
// exhaust the stack, broken GLB chunk lengths, non-finite transforms.
#include <sys/stat.h>

#include <fcntl.h>
#include <unistd.h>
#include <atomic>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "robustness_support.h"
#include "sample_inputs.h"
#include "scene/gltf.h"
#include "scene/gltf_animation.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::fresh_folder;
using test::loads_or_fails_cleanly;
using test::write_text;

// What the renderer relies on in a loaded mesh.
void expect_sound_mesh(const Mesh& mesh, const std::string& what) {
    ASSERT_FALSE(mesh.indices.empty()) << what;
    EXPECT_EQ(mesh.indices.size() % 3, 0u) << what;
    ASSERT_EQ(mesh.normals.size(), mesh.positions.size()) << what;
    for (const std::uint32_t i : mesh.indices) ASSERT_LT(i, mesh.positions.size()) << what;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        for (int k = 0; k < 3; ++k) {
            ASSERT_TRUE(std::isfinite(mesh.positions[v][k])) << what << " position " << v;
            ASSERT_TRUE(std::isfinite(mesh.normals[v][k])) << what << " normal " << v;
        }
}

void expect_sound_model(const GltfModel& model, const std::string& what) {
    ASSERT_FALSE(model.parts.empty()) << what;
    for (const GltfPart& part : model.parts) expect_sound_mesh(*part.mesh, what);
}

// Loads `file` expecting an InputError whose one line names it and contains `expected`.
void expect_input_error(const fs::path& file, const std::string& expected) {
    try {
        load_gltf(file);
        ADD_FAILURE() << file << " loaded";
    } catch (const InputError& e) {
        EXPECT_TRUE(test::is_one_line_naming(e.what(), file));
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
}

json sample_document(const fs::path& dir) {
    test::write_sample_gltf_embedded(dir / "sample.gltf");
    return json::parse(test::read_text(dir / "sample.gltf"));
}

TEST(RobustGltf, TheSampleModelsLoadWithTheirKnownShape) {
    const fs::path dir = fresh_folder();
    test::write_sample_glb(dir / "box.glb");
    test::write_sample_gltf_embedded(dir / "embedded.gltf");
    test::write_sample_gltf_external(dir / "external.gltf");
    for (const char* name : {"box.glb", "embedded.gltf", "external.gltf"}) {
        // A unit box turned 45 degrees about +Y and lifted by 0.5: x and z reach +-sqrt(1/2).
        const GltfModel model = load_gltf(dir / name);
        EXPECT_EQ(model.triangle_count(), 12u) << name;
        EXPECT_NEAR(model.bounds_max.x, std::sqrt(0.5f), 1e-5f) << name;
        EXPECT_NEAR(model.bounds_min.z, -std::sqrt(0.5f), 1e-5f) << name;
        EXPECT_NEAR(model.bounds_min.y, 0.0f, 1e-6f) << name;
        EXPECT_NEAR(model.bounds_max.y, 1.0f, 1e-6f) << name;
        // Its one material, base colour (0.8, 0.2, 0.2) and the glTF defaults metallic 1, roughness 1:
        // a metal (rho_d 0), F0 = the base colour, rho_s = luminance(F0) (n + 1) / (n + 2) at n = 1.
        ASSERT_EQ(model.parts.size(), 1u) << name;
        EXPECT_EQ(model.parts[0].material.rho_d, glm::vec3(0.0f)) << name;
        EXPECT_NEAR(model.parts[0].material.rho_s, (0.2126f * 0.8f + 0.7152f * 0.2f + 0.0722f * 0.2f) * 2.0f / 3.0f,
                    1e-6f)
            << name;
    }
    // A 4-vertex strip (two triangles) under a matrix scaling by 2 and moving +1 along x.
    test::write_sample_gltf_interleaved_strip(dir / "strip.gltf");
    const GltfModel strip = load_gltf(dir / "strip.gltf");
    EXPECT_EQ(strip.triangle_count(), 2u);
    EXPECT_EQ(strip.bounds_min, glm::vec3(1, 0, 0));
    EXPECT_EQ(strip.bounds_max, glm::vec3(3, 2, 0));
}

TEST(RobustGltf, TheTexturedAndAnimatedSamplesLoadWithWhatTheyHold) {
    const fs::path dir = fresh_folder();
    test::write_sample_gltf_textured(dir / "textured.gltf");
    const GltfModel textured = load_gltf(dir / "textured.gltf");
    ASSERT_EQ(textured.parts.size(), 1u);
    ASSERT_TRUE(textured.parts[0].material.base_color_texture.has_value());
    EXPECT_EQ(textured.parts[0].material.base_color_texture->image->width, 4);
    EXPECT_EQ(textured.parts[0].mesh->texcoords.size(), textured.parts[0].mesh->positions.size());
    // The transform (offset 0.5 in u, scale 2 in u): u spans 0.5 ... 2.5, v 0 ... 1.
    float u_max = 0.0f;
    for (const glm::vec2& uv : textured.parts[0].mesh->texcoords) u_max = std::max(u_max, uv.x);
    EXPECT_NEAR(u_max, 2.5f, 1e-6f);

    test::write_sample_gltf_animated(dir / "animated.gltf");
    const GltfModel animated = load_gltf(dir / "animated.gltf");
    ASSERT_TRUE(animated.rig);
    ASSERT_EQ(animated.rig->clips.size(), 1u);
    EXPECT_EQ(animated.rig->clips[0].name, "bend");
    EXPECT_NEAR(animated.rig->clips[0].duration, 2.0, 1e-9);
    EXPECT_EQ(animated.rig->skins.size(), 1u);
    ASSERT_EQ(animated.parts.size(), 1u);
    EXPECT_TRUE(animated.parts[0].sources->skinned);
    EXPECT_TRUE(animated.parts[0].sources->morphed);
}

TEST(RobustGltf, EveryTruncatedGlbIsRefused) {
    const fs::path dir = fresh_folder();
    const std::vector<std::uint8_t> whole = test::sample_glb_bytes();
    const fs::path file = dir / "cut.glb";
    for (const std::size_t n : test::truncation_lengths(whole.size(), whole.size(), 0)) {
        test::write_bytes(file, std::vector<std::uint8_t>(whole.begin(), whole.begin() + std::ptrdiff_t(n)));
        EXPECT_FALSE(loads_or_fails_cleanly(
            file, [&] { load_gltf(file); }, "first " + std::to_string(n) + " bytes"))
            << "a .glb cut to " << n << " of " << whole.size() << " bytes loaded";
    }
}

TEST(RobustGltf, EveryTruncatedGltfIsRefused) {
    const fs::path dir = fresh_folder();
    test::write_sample_gltf_embedded(dir / "whole.gltf");
    const std::vector<std::uint8_t> whole = test::read_bytes(dir / "whole.gltf");
    const fs::path file = dir / "cut.gltf";
    for (const std::size_t n : test::truncation_lengths(whole.size(), 600, 200)) {
        test::write_bytes(file, std::vector<std::uint8_t>(whole.begin(), whole.begin() + std::ptrdiff_t(n)));
        EXPECT_FALSE(loads_or_fails_cleanly(
            file, [&] { load_gltf(file); }, "first " + std::to_string(n) + " bytes"))
            << "a .gltf cut to " << n << " of " << whole.size() << " bytes loaded";
    }
}

TEST(RobustGltf, BitFlippedGlbLoadsSoundlyOrIsRefused) {
    const fs::path dir = fresh_folder();
    const fs::path file = dir / "flipped.glb";
    int index = 0;
    for (const auto& bytes : test::bit_flipped(test::sample_glb_bytes(), 1500, 20240601)) {
        test::write_bytes(file, bytes);
        const std::string what = "mutant " + std::to_string(index++);
        loads_or_fails_cleanly(
            file, [&] { expect_sound_model(load_gltf(file), what); }, what);
    }
}

TEST(RobustGltf, BitFlippedEmbeddedGltfLoadsSoundlyOrIsRefused) {
    const fs::path dir = fresh_folder();
    test::write_sample_gltf_embedded(dir / "whole.gltf");
    const fs::path file = dir / "flipped.gltf";
    int index = 0;
    for (const auto& bytes : test::bit_flipped(test::read_bytes(dir / "whole.gltf"), 1500, 7)) {
        test::write_bytes(file, bytes);
        const std::string what = "mutant " + std::to_string(index++);
        loads_or_fails_cleanly(
            file, [&] { expect_sound_model(load_gltf(file), what); }, what);
    }
}

TEST(RobustGltf, ExternalBufferShorterThanDeclaredIsRefused) {
    const fs::path dir = fresh_folder();
    test::write_sample_gltf_external(dir / "short.gltf");
    const auto bin = test::read_bytes(dir / "short.bin");
    test::write_bytes(dir / "short.bin", std::vector<std::uint8_t>(bin.begin(), bin.begin() + 100));
    expect_input_error(dir / "short.gltf", "short.bin");
}

TEST(RobustGltf, BufferUrisOnSpecialFilesAreRefused) {
    const fs::path dir = fresh_folder();
    fs::create_directory(dir / "folder.bin");
    // A device, a folder, a procfs file (regular but of size 0), no name at all.
    for (const std::string uri : {"/dev/zero", "folder.bin", "/proc/self/status", ""}) {
        json doc = sample_document(dir);
        doc["buffers"][0]["uri"] = uri;
        write_text(dir / "special.gltf", doc.dump());
        const fs::path file = dir / "special.gltf";
        EXPECT_FALSE(loads_or_fails_cleanly(
            file, [&] { load_gltf(file); }, uri))
            << uri;
    }
}

// tinygltf reads image files even when textures are not decoded: opening a FIFO with no writer would
// block for ever. The image must be skipped (textures are unused) or refused, quickly either way.
TEST(RobustGltf, AnImageUriOnAFifoDoesNotHang) {
    const fs::path dir = fresh_folder();
    const fs::path fifo = dir / "texture.png";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    json doc = sample_document(dir);
    doc["images"] = json::array({{{"uri", "texture.png"}}});
    doc["textures"] = json::array({{{"source", 0}}});
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    write_text(dir / "fifo.gltf", doc.dump());

    std::atomic<bool> finished{false};
    std::thread loader([&] {
        loads_or_fails_cleanly(
            dir / "fifo.gltf", [&] { load_gltf(dir / "fifo.gltf"); }, "image on a FIFO");
        finished = true;
    });
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (!finished && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    EXPECT_TRUE(finished) << "load_gltf blocked on the FIFO";
    if (!finished) {  // release it: a writer opening the FIFO unblocks the reader's open()
        const int fd = ::open(fifo.c_str(), O_WRONLY);
        if (fd >= 0) ::close(fd);
    }
    loader.join();
}

TEST(RobustGltf, ADeepNodeChainIsRefusedNotAStackOverflow) {
    const fs::path dir = fresh_folder();
    json doc = sample_document(dir);
    const int depth = 2000;  // over the 1000-level limit
    json nodes = json::array();
    for (int i = 0; i < depth; ++i) nodes.push_back(i + 1 < depth ? json{{"children", {i + 1}}} : json{{"mesh", 0}});
    doc["nodes"] = std::move(nodes);
    doc["scenes"] = json::array({{{"nodes", {0}}}});
    write_text(dir / "deep.gltf", doc.dump());
    expect_input_error(dir / "deep.gltf", "deeper than");
}

TEST(RobustGltf, DeeplyNestedJsonIsRefusedNotAStackOverflow) {
    const fs::path dir = fresh_folder();
    const std::string document = sample_document(dir).dump();
    const std::string nested = std::string(200000, '[') + std::string(200000, ']');
    // In "extras" (which tinygltf converts recursively) and as a whole document.
    write_text(dir / "extras.gltf", document.substr(0, document.size() - 1) + ",\"extras\":" + nested + "}");
    expect_input_error(dir / "extras.gltf", "nested");
    write_text(dir / "array.gltf", nested);
    expect_input_error(dir / "array.gltf", "nested");
}

TEST(RobustGltf, GlbChunkLengthsThatLieAreRefused) {
    const fs::path dir = fresh_folder();
    const std::vector<std::uint8_t> whole = test::sample_glb_bytes();
    auto with_u32 = [&](std::size_t at, std::uint32_t value) {
        std::vector<std::uint8_t> bytes = whole;
        for (int i = 0; i < 4; ++i) bytes[at + std::size_t(i)] = std::uint8_t(value >> (8 * i));
        return bytes;
    };
    std::uint32_t json_length = 0;
    for (int i = 0; i < 4; ++i) json_length |= std::uint32_t(whole[12 + std::size_t(i)]) << (8 * i);
    const std::size_t bin_header = 20 + json_length;
    const struct {
        const char* name;
        std::vector<std::uint8_t> bytes;
    } cases[] = {
        {"total_huge", with_u32(8, 0xFFFFFFF0u)},
        {"json_huge", with_u32(12, 0xFFFFFFF0u)},
        {"json_past_end", with_u32(12, std::uint32_t(whole.size()))},
        {"bin_huge", with_u32(bin_header, 0xFFFFFFF0u)},
        {"bin_short", with_u32(bin_header, 16)},
    };
    for (const auto& c : cases) {
        const fs::path file = dir / (std::string(c.name) + ".glb");
        test::write_bytes(file, c.bytes);
        EXPECT_FALSE(loads_or_fails_cleanly(
            file, [&] { load_gltf(file); }, c.name))
            << c.name << " loaded";
    }
}

TEST(RobustGltf, TransformsPastTheCoordinateLimitAreRefused) {
    const fs::path dir = fresh_folder();
    json doc = sample_document(dir);
    doc["nodes"][0]["translation"] = {2e12, 0, 0};
    write_text(dir / "far.gltf", doc.dump());
    expect_input_error(dir / "far.gltf", "POSITION 0 lies beyond 1e12 after its node transforms (coordinate limit)");

    // Finite numbers whose product is not even a double.
    doc = sample_document(dir);
    doc["nodes"][0]["scale"] = {1e300, 1e300, 1e300};
    doc["nodes"][1].erase("rotation");
    doc["nodes"][1].erase("scale");
    doc["nodes"][1]["matrix"] = {1e300, 0, 0, 0, 0, 1e300, 0, 0, 0, 0, 1e300, 0, 0, 0, 0, 1};
    write_text(dir / "matrix.gltf", doc.dump());
    expect_input_error(dir / "matrix.gltf", "is not finite");
}

TEST(RobustGltf, AZeroScaleNodeGivesASoundMesh) {
    // Its normal matrix has no inverse: normals become non-finite and must be replaced.
    const fs::path dir = fresh_folder();
    json doc = sample_document(dir);
    doc["nodes"][1]["scale"] = {1, 0, 1};
    write_text(dir / "flat.gltf", doc.dump());
    const fs::path file = dir / "flat.gltf";
    EXPECT_TRUE(loads_or_fails_cleanly(
        file, [&] { expect_sound_model(load_gltf(file), "flat"); }, "flat"));
}

}  // namespace
}  // namespace envshadow
