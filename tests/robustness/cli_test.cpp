// The envshadow executable on bad flags and bad inputs (docs/DESIGN.md §6): exit code 2 for usage and 3
// for input, one line on stderr naming the option or the file, and nothing left in the folder, no
// output and no temporary; a failed run keeps an earlier output. Every case here fails before a GL
// context is made (cli_gl_test.cpp has the ones that render).
#include <sys/stat.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_support.h"
#include "robustness_support.h"
#include "sample_inputs.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
using test::fails_with;
using test::files_in;
using test::run_envshadow;
using test::write_text;

std::vector<std::uint8_t> prefix(const std::vector<std::uint8_t>& bytes, std::size_t n) {
    return std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + std::ptrdiff_t(n));
}

// A folder holding a small valid scene (scene.json: a box model and a sphere under sky.hdr), its
// model, and valid maps; tests add broken files beside them.
fs::path inputs_folder() {
    const fs::path dir = test::fresh_folder();
    test::write_sample_glb(dir / "box.glb");
    test::write_sample_hdr(dir / "sky.hdr", 64, 32, true);
    test::write_sample_exr(dir / "sky.exr", 64, 32);
    write_text(dir / "scene.json",
               R"({"environment": "sky.hdr", "objects": [{"model": "box.glb"}, {"mesh": "sphere"}]})");
    return dir;
}

struct BadRun {
    std::vector<std::string> args;
    std::vector<std::string> named;  // what the one line must contain
};

// Runs each case in `dir`: exit `code`, one line naming what it should, and the folder unchanged.
void expect_each_fails(const fs::path& dir, const std::vector<BadRun>& cases, int code) {
    const auto before = files_in(dir);
    for (const BadRun& c : cases) {
        const test::CliRun run = run_envshadow(c.args, dir);
        EXPECT_TRUE(fails_with(run, code, c.named)) << test::describe(c.args, run);
        EXPECT_EQ(files_in(dir), before) << test::describe(c.args, run) << "left files behind";
    }
}

TEST(CliUsage, ValuesOutOfRangeAndUnknownNamesAreUsageErrors) {
    const fs::path dir = inputs_folder();
    const std::vector<std::string> render = {"render", "--scene", "scene.json", "--out", "out.png"};
    auto with = [&](std::vector<std::string> base, std::initializer_list<std::string> extra) {
        base.insert(base.end(), extra);
        return base;
    };
    const std::vector<std::string> decompose = {"decompose", "--env", "sky.hdr", "--json", "cells.json"};
    const std::vector<std::string> reference = {"reference", "--scene", "scene.json", "--exr", "ref.exr"};
    const std::vector<std::string> bench = {"bench", "--scene", "scene.json", "--json", "bench.json"};
    expect_each_fails(dir,
                      {
                          {{"frobnicate"}, {"frobnicate"}},
                          {with(render, {"--lights", "0"}), {"--lights"}},
                          {with(render, {"--lights", "1000000"}), {"--lights"}},
                          {with(render, {"--lights", "-1"}), {"--lights"}},
                          {with(render, {"--lights", "many"}), {"--lights"}},
                          {with(render, {"--width", "-1"}), {"--width"}},
                          {with(render, {"--width", "0"}), {"--width"}},
                          {with(render, {"--width", "100000"}), {"--width"}},
                          {with(render, {"--height", "7"}), {"--height"}},
                          {with(render, {"--tile", "7"}), {"--tile"}},
                          {with(render, {"--tile", "100000"}), {"--tile"}},
                          {with(render, {"--backend", "vulkan"}), {"--backend"}},
                          {with(render, {"--method", "bogus"}), {"bogus"}},
                          {with(render, {"--depth-bits", "24"}), {"--depth-bits"}},
                          {with(render, {"--frames", "0"}), {"--frames"}},
                          {with(render, {"--time", "nan"}), {"--time"}},
                          {with(render, {"--time", "inf"}), {"--time"}},
                          {with(render, {"--no-such-flag"}), {"--no-such-flag"}},
                          {{"render", "--out", "out.png"}, {"--scene"}},
                          {{"render", "--scene", "scene.json"}, {"--out"}},
                          {with(decompose, {"--lights", "0"}), {"--lights"}},
                          {with(decompose, {"--lights", "1000000"}), {"--lights"}},
                          {with(decompose, {"--method", "kmeans"}), {"--method"}},
                          {{"decompose", "--lights", "8"}, {"--env"}},
                          {with(reference, {"--width", "0"}), {"--width"}},
                          {with(reference, {"--samples", "0"}), {"--samples"}},
                          {with(reference, {"--time", "nan"}), {"--time"}},
                          {with(reference, {"--error", "nan"}), {"--error"}},
                          {with(bench, {"--time-step", "nan"}), {"--time-step"}},
                          {{"compare", "a.exr", "b.exr", "--diff-scale", "nan"}, {"--diff-scale"}},
                          {with(bench, {"--frames", "0"}), {"--frames"}},
                          {with(bench, {"--tile", "7"}), {"--tile"}},
                          {with(bench, {"--sweep", "lights=0"}), {"--sweep"}},
                          {with(bench, {"--sweep", "resolution=99999x99999"}), {"--sweep"}},
                          {{"compare", "a.exr"}, {"b"}},
                      },
                      2);
}

TEST(CliInput, BrokenScenesAndModelsAreInputErrors) {
    const fs::path dir = inputs_folder();
    const auto scene = test::read_bytes(dir / "scene.json");
    test::write_bytes(dir / "cut.json", prefix(scene, scene.size() / 2));
    write_text(dir / "lost_model.json", R"({"objects": [{"model": "lost.glb"}]})");
    write_text(dir / "key.json", "{\"objects\": [{\"mesh\": \"box\", \"colour\\n\": 1}]}");
    const auto glb = test::sample_glb_bytes();
    test::write_bytes(dir / "cut.glb", prefix(glb, glb.size() - 10));
    // A textured model whose PNG is cut in half, and one whose PNG is missing.
    test::write_sample_gltf_textured(dir / "cut_texture.gltf", "cut_texture.png");
    const auto png = test::read_bytes(dir / "cut_texture.png");
    test::write_bytes(dir / "cut_texture.png", prefix(png, png.size() / 2));
    test::write_sample_gltf_textured(dir / "lost_texture.gltf", "lost_texture.png");
    fs::remove(dir / "lost_texture.png");
    // An animated model whose skin lost a joint (the strip's top follows joint 1), and one whose
    // sampler names an interpolation glTF does not have.
    test::write_sample_gltf_animated(dir / "animated.gltf");
    nlohmann::json animated = nlohmann::json::parse(test::read_text(dir / "animated.gltf"));
    animated["skins"][0]["joints"] = {1};
    write_text(dir / "lost_joint.gltf", animated.dump());
    animated = nlohmann::json::parse(test::read_text(dir / "animated.gltf"));
    animated["animations"][0]["samplers"][0]["interpolation"] = "BEZIER";
    write_text(dir / "bezier.gltf", animated.dump());
    ASSERT_EQ(::mkfifo((dir / "pipe.json").c_str(), 0600), 0);
    const auto out = std::vector<std::string>{"--out", "out.png"};
    auto render = [&](const std::string& scene_file) {
        std::vector<std::string> args = {"render", "--scene", scene_file};
        args.insert(args.end(), out.begin(), out.end());
        return args;
    };
    expect_each_fails(dir,
                      {
                          {render("missing.json"), {"missing.json"}},
                          {render("cut.json"), {"cut.json", "invalid JSON"}},
                          {render("lost_model.json"), {"lost_model.json", "lost.glb"}},
                          {render("key.json"), {"key.json", "colour\\n"}},
                          {render("cut.glb"), {"cut.glb"}},
                          {render("cut_texture.gltf"), {"cut_texture.gltf", "image 0: cannot decode it"}},
                          {render("lost_texture.gltf"), {"lost_texture.gltf", "lost_texture.png not found"}},
                          {{"reference", "--scene", "cut_texture.gltf", "--exr", "ref.exr"}, {"cut_texture.gltf"}},
                          {render("lost_joint.gltf"), {"lost_joint.gltf", "past skin 0's 1 joints"}},
                          {render("bezier.gltf"), {"bezier.gltf", "interpolation \"BEZIER\""}},
                          {{"reference", "--scene", "lost_joint.gltf", "--exr", "ref.exr"}, {"lost_joint.gltf"}},
                          {render("pipe.json"), {"pipe.json"}},
                          {{"reference", "--scene", "cut.glb", "--exr", "ref.exr"}, {"cut.glb"}},
                          {{"bench", "--scene", "cut.json"}, {"cut.json"}},
                      },
                      3);
}

TEST(CliInput, BrokenMapsAreInputErrors) {
    const fs::path dir = inputs_folder();
    const auto hdr = test::read_bytes(dir / "sky.hdr");
    test::write_bytes(dir / "cut.hdr", prefix(hdr, hdr.size() - 40));  // inside the last scanline
    const auto exr = test::read_bytes(dir / "sky.exr");
    test::write_bytes(dir / "cut.exr", prefix(exr, exr.size() * 2 / 3));
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    std::vector<glm::vec3> texels(8, glm::vec3(1.0f));
    texels[3] = glm::vec3(nan, 1, 1);
    test::write_exr_texels(dir / "nan.exr", 4, 2, texels);
    texels[3] = glm::vec3(1, inf, 1);
    test::write_exr_texels(dir / "inf.exr", 4, 2, texels);
    test::write_exr_texels(dir / "square.exr", 4, 4, std::vector<glm::vec3>(16, glm::vec3(1.0f)));
    write_text(dir / "text.hdr", "just some text\n");
    ASSERT_EQ(::mkfifo((dir / "pipe.exr").c_str(), 0600), 0);
    auto decompose = [](const std::string& map) {
        return std::vector<std::string>{"decompose", "--env",      map,     "--lights", "8",
                                        "--json",    "cells.json", "--png", "cells.png"};
    };
    expect_each_fails(dir,
                      {
                          {decompose("missing.exr"), {"missing.exr"}},
                          {decompose("cut.hdr"), {"cut.hdr", "truncated"}},
                          {decompose("cut.exr"), {"cut.exr"}},
                          {decompose("nan.exr"), {"nan.exr", "NaN"}},
                          {decompose("inf.exr"), {"inf.exr"}},
                          {decompose("square.exr"), {"square.exr", "4x4"}},
                          {decompose("text.hdr"), {"text.hdr"}},
                          {decompose("pipe.exr"), {"pipe.exr"}},
                          {decompose("builtin:sky:elevation=400"), {"elevation"}},
                          {decompose("builtin:nothing"), {"builtin:nothing"}},
                          {{"render", "--scene", "scene.json", "--env", "cut.hdr", "--out", "out.png"}, {"cut.hdr"}},
                          {{"reference", "--scene", "scene.json", "--env", "nan.exr", "--exr", "ref.exr"}, {"nan.exr"}},
                          {{"compare", "cut.exr", "sky.exr"}, {"cut.exr"}},
                          {{"compare", "sky.exr", "sky.exr", "--mask", "missing.png"}, {"missing.png"}},
                      },
                      3);
}

TEST(CliInput, TinyAndBlackMapsGiveWellDefinedLightsOrAClearError) {
    // A 2x1 map and an all-black one: either cells with finite, non-negative values, or exit 3.
    const fs::path dir = test::fresh_folder();
    test::write_exr_texels(dir / "tiny.exr", 2, 1, {glm::vec3(1.0f), glm::vec3(2.0f)});
    test::write_exr_texels(dir / "black.exr", 8, 4, std::vector<glm::vec3>(32, glm::vec3(0.0f)));
    for (const char* map : {"tiny.exr", "black.exr"})
        for (const char* method : {"lloyd", "ccvt", "mediancut", "random", "fs"}) {
            const std::vector<std::string> args = {"decompose", "--env", map,      "--lights",  "16",
                                                   "--method",  method,  "--json", "cells.json"};
            const test::CliRun run = run_envshadow(args, dir);
            if (run.exit_code == 3) {
                EXPECT_TRUE(fails_with(run, 3, {map})) << test::describe(args, run);
                EXPECT_FALSE(fs::exists(dir / "cells.json")) << test::describe(args, run);
                continue;
            }
            ASSERT_EQ(run.exit_code, 0) << test::describe(args, run);
            const std::string json = test::read_text(dir / "cells.json");
            EXPECT_EQ(json.find("nan"), std::string::npos) << test::describe(args, run) << json;
            EXPECT_EQ(json.find("inf"), std::string::npos) << test::describe(args, run) << json;
            EXPECT_EQ(json.find("null"), std::string::npos) << test::describe(args, run) << json;
            fs::remove(dir / "cells.json");
        }
}

TEST(CliOutput, AFailedRunKeepsTheEarlierOutputAndLeavesNoTemporary) {
    const fs::path dir = inputs_folder();
    write_text(dir / "cells.json", "earlier");
    write_text(dir / "out.png", "earlier");
    const auto before = files_in(dir);
    const std::vector<std::vector<std::string>> runs = {
        {"decompose", "--env", "missing.hdr", "--lights", "8", "--json", "cells.json"},
        {"render", "--scene", "missing.json", "--out", "out.png"},
    };
    for (const auto& args : runs) {
        const test::CliRun run = run_envshadow(args, dir);
        EXPECT_EQ(run.exit_code, 3) << test::describe(args, run);
        EXPECT_EQ(files_in(dir), before) << test::describe(args, run);
    }
    EXPECT_EQ(test::read_text(dir / "cells.json"), "earlier");
    EXPECT_EQ(test::read_text(dir / "out.png"), "earlier");
}

TEST(CliOutput, OutputsIntoAMissingFolderFailCleanly) {
    const fs::path dir = inputs_folder();
    const auto before = files_in(dir);
    const std::vector<std::string> args = {
        "decompose", "--env", "sky.hdr", "--lights", "4", "--json", "no/such/folder/cells.json"};
    const test::CliRun run = run_envshadow(args, dir);
    EXPECT_TRUE(fails_with(run, 3, {"no/such/folder/cells.json"})) << test::describe(args, run);
    EXPECT_EQ(files_in(dir), before) << test::describe(args, run);
}

TEST(CliOutput, DecomposeWritesItsOutputsAndNoTemporary) {
    const fs::path dir = inputs_folder();
    auto expected = files_in(dir);
    const std::vector<std::string> args = {"decompose", "--env",      "sky.exr", "--lights", "8",
                                           "--json",    "cells.json", "--png",   "cells.png"};
    const test::CliRun run = run_envshadow(args, dir);
    ASSERT_EQ(run.exit_code, 0) << test::describe(args, run);
    expected.insert({"cells.json", "cells.png"});
    EXPECT_EQ(files_in(dir), expected);
}

}  // namespace
}  // namespace envshadow
