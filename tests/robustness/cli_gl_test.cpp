// The envshadow executable where it renders (a GL context, EGL or OSMesa): outputs written whole and
// no temporary left, an output into a missing folder failing cleanly, and the GPU limit on the
// shadow atlas queried, not assumed: an atlas over GL_MAX_TEXTURE_SIZE shrinks its tiles and says so.
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli_support.h"
#include "robustness_support.h"
#include "sample_inputs.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
using test::files_in;
using test::run_envshadow;

fs::path scene_folder() {
    const fs::path dir = test::fresh_folder();
    test::write_sample_glb(dir / "box.glb");
    const std::string scene =
        R"({"environment": "builtin:sky", "objects": [{"mesh": {"type": "plane", "size": 6}, "ground": true},
            {"model": "box.glb"}, {"mesh": "sphere", "transform": {"translation": [1.2, 0.5, 0]}}]})";
    test::write_bytes(dir / "scene.json", std::vector<std::uint8_t>(scene.begin(), scene.end()));
    return dir;
}

TEST(CliRender, WritesBothOutputsWholeAndNoTemporary) {
    const fs::path dir = scene_folder();
    auto expected = files_in(dir);
    for (const char* backend : {"egl", "osmesa"}) {
        const std::vector<std::string> args = {"render", "--scene",  "scene.json", "--backend", backend,  "--width",
                                               "64",     "--height", "32",         "--lights",  "8",      "--tile",
                                               "128",    "--out",    "out.png",    "--exr",     "out.exr"};
        const test::CliRun run = run_envshadow(args, dir, 120);
        ASSERT_EQ(run.exit_code, 0) << test::describe(args, run);
        expected.insert({"out.png", "out.exr"});
        EXPECT_EQ(files_in(dir), expected) << test::describe(args, run);
        // Whole files: PNG's last chunk is IEND; an EXR this small is a few kilobytes at least.
        const std::string png = test::read_text(dir / "out.png");
        ASSERT_GT(png.size(), 12u);
        EXPECT_EQ(png.substr(png.size() - 8, 4), "IEND") << backend;
        EXPECT_GT(fs::file_size(dir / "out.exr"), 2000u) << backend;
    }
}

TEST(CliRender, AnOutputIntoAMissingFolderFailsCleanly) {
    const fs::path dir = scene_folder();
    const auto before = files_in(dir);
    const std::vector<std::string> args = {"render",   "--scene", "scene.json",     "--width", "32",
                                           "--height", "32",      "--lights",       "4",       "--tile",
                                           "128",      "--out",   "missing/out.png"};
    const test::CliRun run = run_envshadow(args, dir, 120);
    EXPECT_TRUE(test::fails_with(run, 3, {"missing/out.png"})) << test::describe(args, run);
    EXPECT_EQ(files_in(dir), before) << test::describe(args, run);
}

TEST(CliRender, AnAtlasOverTheGlTextureLimitShrinksItsTilesAndSaysSo) {
    // 128 cells, about 80 above the ground: 16 columns of 2048 texels = 32768, over llvmpipe's (and
    // most GPUs') 16384. The renderer asks GL for GL_MAX_TEXTURE_SIZE and halves the tile size.
    const fs::path dir = scene_folder();
    const std::vector<std::string> args = {"render",   "--scene", "scene.json", "--width",      "32",
                                           "--height", "32",      "--lights",   "128",          "--tile",
                                           "2048",     "--out",   "out.png",    "--tile-sizes", "uniform"};
    const test::CliRun run = run_envshadow(args, dir, 120);
    ASSERT_EQ(run.exit_code, 0) << test::describe(args, run);
    EXPECT_NE(run.err.find("exceed the GL limit; using 1024^2 tiles"), std::string::npos) << run.err;
    std::smatch atlas;
    ASSERT_TRUE(std::regex_search(run.out, atlas, std::regex(R"(atlas: \d+ tiles of (\d+)\^2 in (\d+)x(\d+))")))
        << run.out;
    EXPECT_EQ(atlas[1], "1024");
    EXPECT_LE(std::stoi(atlas[2]), 16384);
    EXPECT_LE(std::stoi(atlas[3]), 16384);
    EXPECT_TRUE(fs::exists(dir / "out.png"));
}

}  // namespace
}  // namespace envshadow
