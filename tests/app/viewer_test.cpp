// The viewer under Xvfb: starts it on a scene, runs a few frames, captures the window (UI
// included) and checks the picture holds a rendered scene, not an empty or uniform window; and with
// the lights sampled on the GPU every frame, that they follow builtin:sky's moving sun.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <regex>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "common/test_files.h"
#include "core/image.h"
#include "env/environment.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;

// Runs `envshadow view ARGUMENTS --screenshot OUT` under Xvfb; returns its log.
std::string run_viewer(const std::string& arguments, const fs::path& out) {
    EXPECT_EQ(std::system("command -v xvfb-run > /dev/null"), 0)
        << "xvfb-run missing: scripts/install-deps.sh installs it";
    fs::create_directories(out.parent_path());
    fs::remove(out);
    const std::string log = out.string() + ".log";
    const std::string command = "xvfb-run -a -s '-screen 0 1280x720x24' " + std::string(ENVSHADOW_EXE) + " view " +
                                arguments + " --screenshot " + out.string() + " > " + log + " 2>&1";
    // xvfb-run -a can lose the race for a display number to another X server starting at the same
    // moment ("Xvfb failed to start"); that is the harness, not the viewer, so it is tried again.
    int status = -1;
    for (int attempt = 0; attempt < 3 && status != 0; ++attempt) status = std::system(command.c_str());
    const std::string text = test::read_text(log);
    EXPECT_EQ(status, 0) << command << "\n" << text;
    return text;
}

TEST(Viewer, RunsUnderXvfbAndShowsTheSceneAndTheUi) {
    ASSERT_EQ(std::system("command -v xvfb-run > /dev/null"), 0)
        << "xvfb-run missing: scripts/install-deps.sh installs it";
    const fs::path out = fs::path(ENVSHADOW_BINARY_DIR) / "viewer" / "viewer_xvfb.png";
    run_viewer("--scene " + std::string(ENVSHADOW_SOURCE_DIR) +
                   "/assets/scenes/spheres.json --lights 32 --width 1024 --height 576 --frames 12",
               out);
    ASSERT_TRUE(fs::exists(out));
    const Image8 image = read_png(out);
    EXPECT_EQ(image.width, 1024);
    EXPECT_EQ(image.height, 576);
    std::set<unsigned> colours;
    long dark = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = image.at(x, y);
            colours.insert(unsigned(p[0]) << 16 | unsigned(p[1]) << 8 | p[2]);
            dark += p[0] + p[1] + p[2] < 24;
        }
    // A shaded scene behind text and widgets has thousands of colours; a blank window has one.
    EXPECT_GT(colours.size(), 2000u);
    EXPECT_LT(double(dark) / (image.width * image.height), 0.9);
}

// --method fs-gpu: the lights come from the GPU sampler every frame, and builtin:sky's sun moves with
// the animation clock (from 15:00 here, 0.02 hours of sun per second so that it stays up over the run
// even when a loaded machine takes a minute over the ten frames: the clock runs in wall time).
// The brightest light must point at the sun of the sky on screen, whose time the viewer reports.
TEST(Viewer, GpuSampledLightsFollowTheAnimatedSky) {
    const fs::path out = fs::path(ENVSHADOW_BINARY_DIR) / "viewer" / "viewer_fs_gpu.png";
    const std::string log = run_viewer("--scene " + std::string(ENVSHADOW_SOURCE_DIR) +
                                           "/assets/scenes/spheres.json --env builtin:sky --method fs-gpu --lights 32 "
                                           "--time 3 --speed 0.02 --width 640 --height 360 --frames 10",
                                       out);
    ASSERT_TRUE(fs::exists(out));
    const std::regex line(R"(fs-gpu: (\d+) lights in the last frame, the brightest toward \(([-0-9.]+), ([-0-9.]+), )"
                          R"(([-0-9.]+)\) in map space; the sky at animation time ([0-9.]+) s)");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(log, m, line)) << log;
    const int lights = std::stoi(m[1]);
    EXPECT_GE(lights, 1);
    EXPECT_LE(lights, 32);
    const double seconds = std::stod(m[5]);
    EXPECT_GE(seconds, 3.0) << "the sky was not moved to the animation time";
    EXPECT_LT(seconds, 5.0);
    SkyParameters sky;
    sky.time_hours = 12.0 + seconds;
    const glm::dvec3 sun = sun_direction(sky);
    const glm::dvec3 brightest = glm::normalize(glm::dvec3(std::stod(m[2]), std::stod(m[3]), std::stod(m[4])));
    // Within two texels of the 256 x 128 importance map (1.4 degrees each).
    EXPECT_LT(std::acos(std::min(1.0, glm::dot(brightest, sun))) * 180.0 / std::numbers::pi, 3.0)
        << "sun at (" << sun.x << ", " << sun.y << ", " << sun.z << ")";
}

// Dynamic resolution under a synthetic drag (--orbit-frames): with a target no frame can meet, the
// dragged frames are shaded at the smallest scale, a quarter of the window each way; once the
// camera stops the viewer returns to full size and says how soon. With --target-ms 0 it never scales.
TEST(Viewer, DynamicResolutionShadesLessWhileDraggedAndFullSizeOnceStill) {
    const std::string scene = "--scene " + std::string(ENVSHADOW_SOURCE_DIR) +
                              "/assets/scenes/spheres.json --lights 16 --speed 0 --width 1024 --height 576 "
                              "--orbit-frames 6 "
                              "--frames 16";
    const std::regex line(
        R"(dynamic resolution: (\d+) frames while the view changed, median [0-9.]+ ms \([0-9.]+ )"
        R"(FPS\) at scale ([0-9.]+), the last at (\d+)x(\d+), (\d+) sample\(s\) per pixel, (\w+) shadows; )"
        R"(target ([^;]+); ([^;]*); while it changed: the renderer [0-9.]+ ms a frame \(median\), )"
        R"((\d+) atlas passes)");
    std::smatch m;

    const fs::path out = fs::path(ENVSHADOW_BINARY_DIR) / "viewer" / "viewer_dynamic_resolution.png";
    const std::string log = run_viewer(scene + " --target-ms 1", out);
    ASSERT_TRUE(std::regex_search(log, m, line)) << log;
    EXPECT_GE(std::stoi(m[1]), 6);
    EXPECT_DOUBLE_EQ(std::stod(m[2]), 0.25);
    EXPECT_EQ(std::stoi(m[3]), 256);
    EXPECT_EQ(std::stoi(m[4]), 144);
    EXPECT_EQ(std::stoi(m[5]), 1) << "MSAA is dropped while the view moves";
    EXPECT_EQ(m[6].str(), "hard") << "soft shadows are dropped while the view moves";
    EXPECT_EQ(m[7].str(), "1 ms");
    EXPECT_TRUE(m[8].str().starts_with("full size again")) << m[8];
    // spheres.json is still: the atlas is drawn once, for the first frame, and kept while the camera moves.
    EXPECT_LE(std::stoi(m[9]), 1);
    const Image8 window = read_png(out);
    EXPECT_EQ(window.width, 1024);
    EXPECT_EQ(window.height, 576);

    const fs::path off = fs::path(ENVSHADOW_BINARY_DIR) / "viewer" / "viewer_dynamic_resolution_off.png";
    const std::string log_off = run_viewer(scene + " --target-ms 0", off);
    ASSERT_TRUE(std::regex_search(log_off, m, line)) << log_off;
    EXPECT_DOUBLE_EQ(std::stod(m[2]), 1.0);
    EXPECT_EQ(std::stoi(m[3]), 1024);
    EXPECT_EQ(std::stoi(m[4]), 576);
    EXPECT_EQ(std::stoi(m[5]), 4) << "without dynamic resolution the frames keep --msaa's default";
    EXPECT_EQ(m[6].str(), "soft") << "and --shadows' default";
    EXPECT_EQ(m[7].str(), "off");
}

// --tonemap reaches the window: the ground below the panels (the same frame of a still scene) is
// drawn differently under linear than under the default ACES; a value outside the table is bad usage
// before any window opens.
TEST(Viewer, TonemapChangesTheWindowAndABadValueIsRefused) {
    const std::string scene = "--scene " + std::string(ENVSHADOW_SOURCE_DIR) +
                              "/assets/scenes/spheres.json --lights 16 --width 1024 --height 576 --frames 4";
    const fs::path aces = fs::path(ENVSHADOW_BINARY_DIR) / "viewer" / "viewer_tonemap_aces.png";
    const fs::path linear = fs::path(ENVSHADOW_BINARY_DIR) / "viewer" / "viewer_tonemap_linear.png";
    run_viewer(scene, aces);
    run_viewer(scene + " --tonemap linear", linear);
    ASSERT_TRUE(fs::exists(aces));
    ASSERT_TRUE(fs::exists(linear));
    const Image8 a = read_png(aces), b = read_png(linear);
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    double difference = 0.0;
    long count = 0;
    for (int y = 480; y < 570; ++y)  // the ground, left of the cells panel and below the settings
        for (int x = 10; x < 620; ++x, ++count)
            for (int c = 0; c < 3; ++c) difference += std::abs(int(a.at(x, y)[c]) - int(b.at(x, y)[c]));
    EXPECT_GT(difference / (3.0 * double(count)), 2.0) << "mean difference in 8-bit levels";

    const std::string bad = std::string(ENVSHADOW_EXE) + " view --tonemap reinhard > /dev/null 2>&1";
    const int status = std::system(bad.c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 2);
}

}  // namespace
}  // namespace envshadow
