// Renders each scene at a small fixed size (tests/regression/render_flags.txt, shared with
// scripts/update-goldens.sh) through the `envshadow` executable and compares the PNG with its golden.
// On failure the rendered image, the golden and their difference are written side by side into
// build/regression/ and named in the message.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/image_compare.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = ENVSHADOW_SOURCE_DIR;
const fs::path kOutput = fs::path(ENVSHADOW_BINARY_DIR) / "regression";

std::string render_flags() {
    std::ifstream in(kSource / "tests/regression/render_flags.txt");
    std::string flags;
    std::getline(in, flags);
    return flags;
}

std::vector<std::string> scene_names() {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(kSource / "assets/scenes"))
        if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

// Renders `scene` with the shared flags; returns the PNG path (empty on failure, with `log` set).
fs::path render(const fs::path& scene, const std::string& backend, const std::string& tag, std::string& log) {
    fs::create_directories(kOutput);
    const fs::path out = kOutput / (tag + "_" + backend + ".png");
    const fs::path log_file = kOutput / (tag + "_" + backend + ".log");
    fs::remove(out);
    const std::string command = std::string(ENVSHADOW_EXE) + " render --scene '" + scene.string() + "' " +
                                render_flags() + " --backend " + backend + " --out '" + out.string() + "' > '" +
                                log_file.string() + "' 2>&1";
    const int status = std::system(command.c_str());
    std::ifstream in(log_file);
    std::stringstream text;
    text << in.rdbuf();
    log = command + "\n" + text.str();
    return status == 0 && fs::exists(out) ? out : fs::path();
}

::testing::AssertionResult matches(const fs::path& rendered, const fs::path& golden, const std::string& tag) {
    const Image8 a = read_png(rendered), b = read_png(golden);
    const ImageDifference d = compare_images(a, b);
    if (d.within(Tolerance{})) return ::testing::AssertionSuccess() << d.summary();
    const fs::path sheet = kOutput / (tag + "_failure.png");
    write_png(sheet, side_by_side(a, b));
    return ::testing::AssertionFailure() << tag << ": " << d.summary() << "\n  rendered: " << rendered.string()
                                         << "\n  golden:   " << golden.string()
                                         << "\n  rendered | golden | 4x difference: " << sheet.string();
}

struct Case {
    std::string scene;
    std::string backend;
};

// Keeps ctest's test names readable (gtest would print the struct's bytes).
void PrintTo(const Case& c, std::ostream* out) {
    *out << c.scene << "/" << c.backend;
}

class Regression : public ::testing::TestWithParam<Case> {};

TEST_P(Regression, MatchesGolden) {
    const Case c = GetParam();
    const fs::path golden = kSource / "screenshots/golden" / (c.scene + ".png");
    ASSERT_TRUE(fs::exists(golden)) << golden << " is missing: run scripts/update-goldens.sh and look at the images";
    std::string log;
    const fs::path rendered = render(kSource / "assets/scenes" / (c.scene + ".json"), c.backend, c.scene, log);
    ASSERT_FALSE(rendered.empty()) << log;
    EXPECT_TRUE(matches(rendered, golden, c.scene + "_" + c.backend));
}

std::vector<Case> all_cases() {
    std::vector<Case> cases;
    for (const std::string& scene : scene_names())
        for (const char* backend : {"egl", "osmesa"}) cases.push_back({scene, backend});
    return cases;
}

INSTANTIATE_TEST_SUITE_P(Scenes, Regression, ::testing::ValuesIn(all_cases()),
                         [](const ::testing::TestParamInfo<Case>& p) { return p.param.scene + "_" + p.param.backend; });

TEST(RegressionSuite, CoversEveryScene) {
    ASSERT_FALSE(scene_names().empty());
    for (const std::string& scene : scene_names())
        EXPECT_TRUE(fs::exists(kSource / "screenshots/golden" / (scene + ".png"))) << scene << " has no golden";
}

TEST(RegressionSuite, EglAndOsmesaAgree) {
    std::string log;
    const fs::path egl = render(kSource / "assets/scenes/spheres.json", "egl", "agree", log);
    ASSERT_FALSE(egl.empty()) << log;
    const fs::path osmesa = render(kSource / "assets/scenes/spheres.json", "osmesa", "agree", log);
    ASSERT_FALSE(osmesa.empty()) << log;
    EXPECT_TRUE(matches(egl, osmesa, "egl_vs_osmesa"));
}

// The suite can fail: moving the camera by 15 cm must be reported as a difference.
TEST(RegressionSuite, DetectsAMovedCamera) {
    const fs::path original = kSource / "assets/scenes/spheres.json";
    nlohmann::json scene = nlohmann::json::parse(std::ifstream(original));
    scene["camera"]["position"][0] = scene["camera"]["position"][0].get<double>() + 0.15;
    // Keep relative paths working: resolve the environment against the original folder.
    if (scene["environment"].is_object() && scene["environment"].contains("source")) {
        const std::string source = scene["environment"]["source"];
        if (source.rfind("builtin:", 0) != 0 && fs::path(source).is_relative())
            scene["environment"]["source"] = (original.parent_path() / source).string();
    }
    fs::create_directories(kOutput);
    const fs::path moved = kOutput / "spheres_moved_camera.json";
    std::ofstream(moved) << scene.dump(2);
    std::string log;
    const fs::path rendered = render(moved, "egl", "moved_camera", log);
    ASSERT_FALSE(rendered.empty()) << log;
    // The failure is reported as a person needs it: numbers, and the three pictures side by side.
    const fs::path sheet = kOutput / "moved_camera_egl_failure.png";
    fs::remove(sheet);
    const ::testing::AssertionResult result =
        matches(rendered, kSource / "screenshots/golden/spheres.png", "moved_camera_egl");
    EXPECT_FALSE(result) << "a moved camera went unnoticed: " << result.message();
    EXPECT_NE(std::string(result.message()).find(sheet.string()), std::string::npos) << result.message();
    ASSERT_TRUE(fs::exists(sheet));
    const Image8 side_by_side_sheet = read_png(sheet);
    EXPECT_EQ(side_by_side_sheet.width, 3 * read_png(rendered).width);
}

}  // namespace
}  // namespace envshadow
