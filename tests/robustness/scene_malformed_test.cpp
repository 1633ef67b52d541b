// Scene JSON broken in ways tests/scene does not cover: every truncation, random bit flips, JSON deep
// enough to exhaust the stack, scenes past the triangle limit, special files named as inputs.
#include <sys/stat.h>

#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "robustness_support.h"
#include "sample_inputs.h"
#include "scene/scene.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::fresh_folder;
using test::loads_or_fails_cleanly;
using test::write_text;

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// What the renderer relies on in a loaded scene.
void expect_sound_scene(const Scene& scene, const std::string& what) {
    ASSERT_FALSE(scene.objects.empty()) << what;
    for (const Object& object : scene.objects) {
        ASSERT_TRUE(object.mesh) << what;
        ASSERT_FALSE(object.mesh->indices.empty()) << what;
        ASSERT_EQ(object.mesh->normals.size(), object.mesh->positions.size()) << what;
        for (const std::uint32_t i : object.mesh->indices) ASSERT_LT(i, object.mesh->positions.size()) << what;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) ASSERT_TRUE(std::isfinite(object.transform[c][r])) << what;
    }
    EXPECT_TRUE(finite(scene.camera.position) && finite(scene.camera.target)) << what;
    glm::vec3 lo, hi;
    scene.bounds_at(0.0, lo, hi);
    EXPECT_TRUE(finite(lo) && finite(hi)) << what;
}

void expect_input_error(const fs::path& file, const std::string& expected) {
    try {
        load_scene(file);
        ADD_FAILURE() << file << " loaded";
    } catch (const InputError& e) {
        EXPECT_TRUE(test::is_one_line_naming(e.what(), file));
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
}

// A folder with the sample scene, its model and its environment file.
fs::path sample_scene(const fs::path& dir) {
    test::write_sample_glb(dir / "box.glb");
    test::write_sample_hdr(dir / "sky.hdr", 16, 8, true);
    write_text(dir / "scene.json", test::sample_scene_json("box.glb", "sky.hdr"));
    return dir / "scene.json";
}

TEST(RobustScene, TheSampleSceneLoads) {
    const fs::path dir = fresh_folder();
    const Scene scene = load_scene(sample_scene(dir));
    EXPECT_EQ(scene.objects.size(), 8u);
    EXPECT_TRUE(scene.has_ground);
    EXPECT_EQ(scene.environment.source, (dir / "sky.hdr").string());
    expect_sound_scene(scene, "sample");
}

TEST(RobustScene, EveryTruncatedSceneIsRefused) {
    const fs::path dir = fresh_folder();
    const std::vector<std::uint8_t> whole = test::read_bytes(sample_scene(dir));
    const fs::path file = dir / "cut.json";
    for (const std::size_t n : test::truncation_lengths(whole.size(), 400, 300)) {
        test::write_bytes(file, std::vector<std::uint8_t>(whole.begin(), whole.begin() + std::ptrdiff_t(n)));
        EXPECT_FALSE(loads_or_fails_cleanly(
            file, [&] { load_scene(file); }, "first " + std::to_string(n) + " bytes"))
            << "a scene cut to " << n << " of " << whole.size() << " bytes loaded";
    }
}

TEST(RobustScene, BitFlippedScenesLoadSoundlyOrAreRefused) {
    const fs::path dir = fresh_folder();
    const std::vector<std::uint8_t> whole = test::read_bytes(sample_scene(dir));
    const fs::path file = dir / "flipped.json";
    int index = 0;
    for (const auto& bytes : test::bit_flipped(whole, 600, 99)) {
        test::write_bytes(file, bytes);
        const std::string what = "mutant " + std::to_string(index++);
        loads_or_fails_cleanly(
            file, [&] { expect_sound_scene(load_scene(file), what); }, what);
    }
}

TEST(RobustScene, DeeplyNestedJsonIsRefusedNotAStackOverflow) {
    const fs::path dir = fresh_folder();
    const std::string nested = std::string(200000, '[') + std::string(200000, ']');
    write_text(dir / "array.json", nested);
    expect_input_error(dir / "array.json", "nested");
    // Inside a built-in mesh's parameters (which the loader used to print as a cache key).
    write_text(dir / "mesh.json", R"({"objects": [{"mesh": {"type": "sphere", "extra": )" + nested + "}}]}");
    expect_input_error(dir / "mesh.json", "nested");
}

TEST(RobustScene, ScenesOverTheTriangleLimitAreRefusedBeforeBuildingTheMeshes) {
    // 13 spheres of 2 * 2000 * 999 = 3,996,000 triangles each: 51,948,000 in all, over 50,000,000.
    const fs::path dir = fresh_folder();
    json objects = json::array();
    for (int i = 0; i < 13; ++i)
        objects.push_back({{"mesh", {{"type", "sphere"}, {"segments", 2000}, {"radius", 1.0 + 0.01 * i}}}});
    write_text(dir / "heavy.json", json{{"objects", objects}}.dump());
    expect_input_error(dir / "heavy.json", "more than 50000000 triangles");
}

TEST(RobustScene, SpecialFilesAreRefused) {
    const fs::path dir = fresh_folder();
    ASSERT_EQ(::mkfifo((dir / "pipe.json").c_str(), 0600), 0);
    expect_input_error(dir / "pipe.json", "no such scene file");
    expect_input_error("/dev/zero", "no such scene file");
    fs::create_directory(dir / "folder.json");
    expect_input_error(dir / "folder.json", "no such scene file");

    ASSERT_EQ(::mkfifo((dir / "pipe.glb").c_str(), 0600), 0);
    ASSERT_EQ(::mkfifo((dir / "pipe.exr").c_str(), 0600), 0);
    write_text(dir / "model.json", R"({"objects": [{"model": "pipe.glb"}]})");
    expect_input_error(dir / "model.json", "pipe.glb not found");
    write_text(dir / "environment.json", R"({"environment": "pipe.exr", "objects": [{"mesh": "box"}]})");
    expect_input_error(dir / "environment.json", "pipe.exr not found");
}

TEST(RobustScene, CoordinatesPastTheLimitAreRefused) {
    const fs::path dir = fresh_folder();
    test::write_sample_glb(dir / "box.glb");
    const struct {
        const char* name;
        const char* objects;
        const char* expected;
    } cases[] = {
        // Each number is in range; their product (scale times fit times model size) is not a float.
        {"product", R"([{"model": "box.glb", "fit": 1e30, "transform": {"scale": 1e30}}])",
         "objects[0].transform: puts the object beyond 1e12"},
        {"translation", R"([{"mesh": "box", "transform": {"translation": [0, 2e12, 0]}}])",
         "objects[0].transform: puts the object beyond 1e12"},
        {"orbit", R"([{"mesh": "box", "animation": {"type": "orbit", "center": [0, 0, 0], "height": 1.5e12}}])",
         "objects[0].animation: lies beyond 1e12"},
        {"path", R"([{"mesh": "box", "animation": {"type": "path", "points": [[0, 0, 0], [0, 0, -3e12]]}}])",
         "objects[0].animation.points[1]: lies beyond 1e12"},
    };
    for (const auto& c : cases) {
        write_text(dir / (std::string(c.name) + ".json"), std::string(R"({"objects": )") + c.objects + "}");
        expect_input_error(dir / (std::string(c.name) + ".json"), c.expected);
    }
    write_text(dir / "camera.json",
               R"({"camera": {"position": [0, 0, 1e20], "target": [0, 0, 0]}, "objects": [{"mesh": "box"}]})");
    expect_input_error(dir / "camera.json", "camera.position: lies beyond 1e12");
}

}  // namespace
}  // namespace envshadow
