// The rasteriser against the ground truth on 64 x 64 pictures, both through the `envshadow` executable
// (the same scene file, loader, camera and conventions): the white furnace and a diffuse plane under
// builtin:sky's sun must agree within 2% (relative RMSE over the pixels both call object pixels).
// The error here is computed from the two EXRs directly, not by `envshadow compare`.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/test_files.h"
#include "core/image.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
const fs::path kOutput = fs::path(ENVSHADOW_BINARY_DIR) / "raster_agreement_test";

void run(const std::string& arguments, const fs::path& log) {
    const std::string command = std::string(ENVSHADOW_EXE) + " " + arguments + " > '" + log.string() + "' 2>&1";
    const int status = std::system(command.c_str());
    ASSERT_EQ(status, 0) << command << "\n" << test::read_text(log);
}

struct Agreement {
    double relative_rmse = 0.0;  // sqrt(sum |raster - reference|^2 / sum |reference|^2), RGB
    double mean_ratio = 0.0;     // sum raster / sum reference
    int object_pixels = 0;       // alpha 1 in both
    int mask_disagreements = 0;  // object in one picture, background in the other
};

// Renders `scene_json` (written to NAME.json) with both renderers and compares the linear EXRs.
Agreement render_both(const std::string& name, const std::string& scene_json) {
    fs::create_directories(kOutput);
    const fs::path scene = kOutput / (name + ".json");
    std::ofstream(scene) << scene_json;
    const fs::path raster = kOutput / (name + "_raster.exr"), reference = kOutput / (name + "_reference.exr");
    const std::string common = "--scene '" + scene.string() + "' --width 64 --height 64";
    Agreement result;
    run("render " + common + " --lights 64 --tile 128 --backend egl --exr '" + raster.string() + "'",
        kOutput / (name + "_raster.log"));
    run("reference " + common + " --seed 7 --exr '" + reference.string() + "'", kOutput / (name + "_reference.log"));
    if (::testing::Test::HasFatalFailure()) return result;

    const Image a = read_exr(raster).image, b = read_exr(reference).image;
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    double error2 = 0.0, reference2 = 0.0, raster_sum = 0.0, reference_sum = 0.0;
    for (int y = 0; y < b.height; ++y) {
        for (int x = 0; x < b.width; ++x) {
            const glm::vec4 r = a.at(x, y), t = b.at(x, y);
            if ((r.a > 0.5f) != (t.a > 0.5f)) ++result.mask_disagreements;
            if (r.a < 1.0f || t.a < 1.0f) continue;  // edge pixels: coverage differs by renderer
            ++result.object_pixels;
            for (int c = 0; c < 3; ++c) {
                error2 += double(r[c] - t[c]) * double(r[c] - t[c]);
                reference2 += double(t[c]) * double(t[c]);
                raster_sum += r[c];
                reference_sum += t[c];
            }
        }
    }
    result.relative_rmse = std::sqrt(error2 / reference2);
    result.mean_ratio = raster_sum / reference_sum;
    return result;
}

TEST(RasterAgreesWithReference, WhiteFurnace) {
    const Agreement agreement = render_both("furnace", R"({"environment": "builtin:constant",
        "camera": {"position": [0, 0.5, 3], "target": [0, 0, 0], "fov": 45},
        "objects": [{"name": "ball", "mesh": {"type": "sphere", "radius": 1}, "material": {"diffuse": 1.0}}]})");
    ASSERT_GT(agreement.object_pixels, 1500);  // the sphere fills about half the picture
    EXPECT_LT(agreement.mask_disagreements, 64 * 64 / 100) << "the two renderers do not share the camera";
    EXPECT_LT(agreement.relative_rmse, 0.02);
    EXPECT_NEAR(agreement.mean_ratio, 1.0, 0.01);
}

TEST(RasterAgreesWithReference, DiffusePlaneUnderASun) {
    const Agreement agreement = render_both("plane", R"({"environment": "builtin:sky",
        "camera": {"position": [0, 2.5, 2.5], "target": [0, 0, 0], "fov": 45},
        "objects": [{"name": "ground", "mesh": {"type": "plane", "size": 4}, "material": {"diffuse": 0.5}}]})");
    ASSERT_GT(agreement.object_pixels, 2500);
    EXPECT_LT(agreement.mask_disagreements, 64 * 64 / 100) << "the two renderers do not share the camera";
    EXPECT_LT(agreement.relative_rmse, 0.02);
    EXPECT_NEAR(agreement.mean_ratio, 1.0, 0.01);
}

}  // namespace
}  // namespace envshadow
