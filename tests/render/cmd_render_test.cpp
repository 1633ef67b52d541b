// `envshadow render` through the real executable: what it writes and prints, and its exit codes
// (2 for bad usage, 3 for bad input) with no output file left behind.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/image.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = ENVSHADOW_SOURCE_DIR;
const fs::path kOutput = fs::path(ENVSHADOW_BINARY_DIR) / "cmd_render_test";

struct CommandResult {
    int status = -1;
    std::string output;
};

CommandResult render(const std::string& arguments) {
    fs::create_directories(kOutput);
    // One log per test: ctest runs this file's tests in parallel processes.
    const fs::path log =
        kOutput / (std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + ".log");
    const std::string command = std::string(ENVSHADOW_EXE) + " render " + arguments + " > '" + log.string() + "' 2>&1";
    const int raw = std::system(command.c_str());
    CommandResult run;
    run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    run.output = text.str();
    return run;
}

const std::string kSmall = "--width 64 --height 48 --lights 8 --tile 128 --backend osmesa";
std::string scene(const std::string& name) {
    return "--scene '" + (kSource / "assets/scenes" / name).string() + "'";
}

TEST(CmdRender, WritesPngAndExrAndReportsTheFrame) {
    const fs::path png = kOutput / "spheres.png", exr = kOutput / "spheres.exr";
    fs::remove(png);
    fs::remove(exr);
    const CommandResult run =
        render(scene("spheres.json") + " " + kSmall + " --out '" + png.string() + "' --exr '" + exr.string() + "'");
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("decomposition: lloyd, 8 cells"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("bytes"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("shadow atlas"), std::string::npos) << run.output;
    const Image8 picture = read_png(png);
    EXPECT_EQ(picture.width, 64);
    EXPECT_EQ(picture.height, 48);
    const ExrContents linear = read_exr(exr);
    ASSERT_TRUE(linear.had_alpha);
    EXPECT_EQ(linear.image.at(1, 1).a, 0.0f);    // the environment above the horizon
    EXPECT_EQ(linear.image.at(32, 40).a, 1.0f);  // the ground in front of the spheres
}

TEST(CmdRender, GpuFloydSteinbergGivesTheLights) {
    const fs::path png = kOutput / "fs_gpu.png";
    fs::remove(png);
    const CommandResult run =
        render(scene("spheres.json") + " " + kSmall + " --method fs-gpu --out '" + png.string() + "'");
    ASSERT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("fs-gpu: "), std::string::npos) << run.output;  // lights sampled every frame
    // interior.exr is 1024 x 512: by default the CPU method fs's blocks (the largest power of two leaving at
    // least 64 blocks per sample). spheres.json has a ground, so only the upper half of the map is sampled:
    // blocks of 16 x 16 texels for 8 samples; over the whole sphere 32 x 32.
    EXPECT_NE(run.output.find("from a 64x32 importance map"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("upper hemisphere"), std::string::npos) << run.output;
    EXPECT_TRUE(fs::exists(png));
    const CommandResult whole = render(scene("spheres.json") + " " + kSmall +
                                       " --method fs-gpu --hemisphere full --out '" + png.string() + "'");
    ASSERT_EQ(whole.status, 0) << whole.output;
    EXPECT_NE(whole.output.find("from a 32x16 importance map"), std::string::npos) << whole.output;
    const CommandResult sized = render(scene("spheres.json") + " " + kSmall +
                                       " --method fs-gpu --fs-importance 256x128 --out '" + png.string() + "'");
    ASSERT_EQ(sized.status, 0) << sized.output;
    EXPECT_NE(sized.output.find("from a 256x128 importance map"), std::string::npos) << sized.output;
}

TEST(CmdRender, BadValuesAreUsageErrors) {
    const fs::path png = kOutput / "bad.png";
    fs::remove(png);
    const std::string out = " --out '" + png.string() + "'";
    for (const std::string& bad :
         {std::string("--lights 0"), std::string("--lights 257"), std::string("--tile 64"),
          std::string("--depth-bits 24"), std::string("--pcf 3x3"), std::string("--specular double"),
          std::string("--cap round"), std::string("--diffuse both"), std::string("--method nope"),
          std::string("--backend vulkan"), std::string("--width 0"),
          std::string("--method fs-gpu --fs-importance 100x50"),
          std::string("--method fs-gpu --fs-importance 2048x1024")}) {  // more than interior.exr's 1024x512
        const CommandResult run = render(scene("spheres.json") + " " + kSmall + " " + bad + out);
        EXPECT_EQ(run.status, 2) << bad << ": " << run.output;
        EXPECT_FALSE(fs::exists(png)) << bad;
    }
    EXPECT_EQ(render(scene("spheres.json") + " " + kSmall).status, 2);  // neither --out nor --exr
}

TEST(CmdRender, BadFilesAreInputErrors) {
    const fs::path png = kOutput / "missing.png";
    fs::remove(png);
    const std::string out = " --out '" + png.string() + "'";
    CommandResult run = render("--scene '" + (kOutput / "no_such_scene.json").string() + "' " + kSmall + out);
    EXPECT_EQ(run.status, 3) << run.output;
    EXPECT_NE(run.output.find("no_such_scene.json"), std::string::npos) << run.output;
    run = render(scene("spheres.json") + " --env '" + (kOutput / "no_such_map.exr").string() + "' " + kSmall + out);
    EXPECT_EQ(run.status, 3) << run.output;
    EXPECT_NE(run.output.find("no_such_map.exr"), std::string::npos) << run.output;
    EXPECT_FALSE(fs::exists(png));
}

// --msaa: a box against the background, one frame (--accumulate 1). At 4 samples per pixel the silhouette's
// pixels are partly covered (alpha strictly between 0 and 1 in the EXR) and their colour lies between the box's
// and the background's; at 1 sample every pixel is one or the other, unless frames with their sample moved in
// the pixel are averaged (the default --accumulate). A count outside 1, 2, 4, 8 is bad usage, and so is an
// --accumulate outside 1-32.
TEST(CmdRender, MultisamplingBlendsTheSilhouetteAndOneSampleDoesNot) {
    const fs::path scene_file = kOutput / "msaa_box.json";
    {
        fs::create_directories(kOutput);
        std::ofstream out(scene_file);
        out << R"({"environment": {"source": "builtin:constant"},
                   "camera": {"position": [1.2, 1.0, 2.5], "target": [0, 0, 0], "fov": 40},
                   "objects": [{"name": "box", "mesh": {"type": "box", "size": [1, 1, 1]},
                                "transform": {"rotation": [0, 25, 0]}, "material": {"diffuse": 0.2}}]})";
    }
    const auto frame = [&](int samples, const std::string& accumulate) {
        const fs::path exr = kOutput / ("msaa_" + std::to_string(samples) + ".exr");
        fs::remove(exr);
        const CommandResult run = render("--scene '" + scene_file.string() + "' " + kSmall + " --msaa " +
                                         std::to_string(samples) + accumulate + " --exr '" + exr.string() + "'");
        EXPECT_EQ(run.status, 0) << run.output;
        EXPECT_NE(run.output.find("msaa: " + std::to_string(samples) + " samples per pixel"), std::string::npos)
            << run.output;
        return read_exr(exr).image;
    };
    const float background = 1.0f;   // builtin:constant
    for (int samples : {1, 4, 0}) {  // 0: one sample, the default --accumulate
        const Image image = samples == 0 ? frame(1, "") : frame(samples, " --accumulate 1");
        float box_brightest = 0.0f;  // the box's fully covered pixels
        for (const glm::vec4& p : image.pixels)
            if (p.a == 1.0f) box_brightest = std::max(box_brightest, p.r);
        ASSERT_GT(box_brightest, 0.0f);
        ASSERT_LT(box_brightest, 0.5f);  // rho_d 0.2 under a unit sky
        int partial = 0, between = 0;
        for (const glm::vec4& p : image.pixels) {
            if (p.a == 0.0f) {
                EXPECT_EQ(p.r, background);
            }
            if (p.a <= 0.0f || p.a >= 1.0f) continue;
            ++partial;
            between += p.r > box_brightest + 0.02f && p.r < background - 0.02f;
        }
        if (samples == 1) {
            EXPECT_EQ(partial, 0);
        } else {  // four samples, or the frames' samples at one a frame
            EXPECT_GT(partial, 40) << "a box's outline at 64x48 crosses that many pixels";
            EXPECT_EQ(between, partial);
        }
    }

    const fs::path png = kOutput / "msaa_bad.png";
    fs::remove(png);
    const CommandResult bad = render(scene("spheres.json") + " " + kSmall + " --msaa 3 --out '" + png.string() + "'");
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_NE(bad.output.find("--msaa"), std::string::npos) << bad.output;
    EXPECT_EQ(std::count(bad.output.begin(), bad.output.end(), '\n'), 1) << bad.output;  // one line
    EXPECT_FALSE(fs::exists(png));
    for (const char* count : {"0", "33"}) {
        const CommandResult bad_count =
            render(scene("spheres.json") + " " + kSmall + " --accumulate " + count + " --out '" + png.string() + "'");
        EXPECT_EQ(bad_count.status, 2) << bad_count.output;
        EXPECT_NE(bad_count.output.find("--accumulate"), std::string::npos) << bad_count.output;
        EXPECT_EQ(std::count(bad_count.output.begin(), bad_count.output.end(), '\n'), 1) << bad_count.output;
        EXPECT_FALSE(fs::exists(png));
    }
}

// Each --tonemap value renders a different PNG of the same frame; linear clips (a channel brighter
// than 1 in the EXR, at the scene's exposure of 0, is 255); a value outside the table is bad usage.
TEST(CmdRender, EveryToneMapRendersItsOwnPngAndLinearClips) {
    const fs::path exr = kOutput / "tonemap.exr";
    std::vector<Image8> pictures;
    for (const std::string op : {"aces", "agx", "neutral", "linear"}) {
        const fs::path png = kOutput / ("tonemap_" + op + ".png");
        fs::remove(png);
        const CommandResult run = render(scene("spheres.json") + " " + kSmall + " --tonemap " + op + " --out '" +
                                         png.string() + "' --exr '" + exr.string() + "'");
        ASSERT_EQ(run.status, 0) << op << ": " << run.output;
        pictures.push_back(read_png(png));
        ASSERT_EQ(pictures.back().width, 64);
    }
    for (std::size_t a = 0; a < pictures.size(); ++a)
        for (std::size_t b = a + 1; b < pictures.size(); ++b)
            EXPECT_NE(pictures[a].rgba, pictures[b].rgba) << a << " " << b;

    const Image linear = read_exr(exr).image;  // the same frame each time (same seed and settings)
    const Image8& clipped = pictures[3];
    int bright = 0;
    for (std::size_t i = 0; i < linear.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            if (linear.pixels[i][c] > 1.0f) {
                ++bright;
                EXPECT_EQ(int(clipped.rgba[i * 4 + std::size_t(c)]), 255) << "pixel " << i << " channel " << c;
            }
    EXPECT_GT(bright, 0);  // interior.exr's windows and lamps are brighter than 1

    const fs::path bad_png = kOutput / "tonemap_bad.png";
    fs::remove(bad_png);
    EXPECT_EQ(
        render(scene("spheres.json") + " " + kSmall + " --tonemap reinhard --out '" + bad_png.string() + "'").status,
        2);
    EXPECT_FALSE(fs::exists(bad_png));
}

}  // namespace
}  // namespace envshadow
