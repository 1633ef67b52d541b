// The viewer under Xvfb: starts it on a scene, runs a few frames, captures the window (UI
// included) and checks the picture holds a rendered scene, not an empty or uniform window.
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "core/image.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;

TEST(Viewer, RunsUnderXvfbAndShowsTheSceneAndTheUi) {
    ASSERT_EQ(std::system("command -v xvfb-run > /dev/null"), 0) << "xvfb-run missing: scripts/install-deps.sh installs it";
    const fs::path out = fs::path(ENVSHADOW_BINARY_DIR) / "viewer" / "viewer_xvfb.png";
    fs::create_directories(out.parent_path());
    fs::remove(out);
    const std::string command = "xvfb-run -a -s '-screen 0 1280x720x24' " + std::string(ENVSHADOW_EXE) +
                                " view --scene " + std::string(ENVSHADOW_SOURCE_DIR) +
                                "/assets/scenes/spheres.json --lights 32 --width 1024 --height 576 --frames 12 "
                                "--screenshot " + out.string() + " > " + out.string() + ".log 2>&1";
    // xvfb-run -a can lose the race for a display number to another X server starting at the same
    // moment ("Xvfb failed to start"); that is the harness, not the viewer, so it is tried again.
    int status = -1;
    for (int attempt = 0; attempt < 3 && status != 0; ++attempt) status = std::system(command.c_str());
    ASSERT_EQ(status, 0) << command << "\nsee " << out << ".log";
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

}  // namespace
}  // namespace envshadow
