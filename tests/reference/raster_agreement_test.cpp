// The rasteriser against the ground truth on 64 x 64 pictures, both through the `envshadow` executable
// (the same scene file, loader, camera and conventions): the white furnace and a diffuse plane under
// builtin:sky's sun must agree within 2% (relative RMSE over the pixels both call object pixels), and
// so must the sky at a --time, and a glTF model of two materials must show both colours in both. With
// their default settings (multisampling, the box-filtered reference) alpha is the coverage in both.
// The error here is computed from the two EXRs directly, not by `envshadow compare`.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "common/test_files.h"
#include "core/image.h"
#include "scene/gltf_writer.h"

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

// `scene_json` written to NAME.json.
fs::path write_scene(const std::string& name, const std::string& scene_json) {
    fs::create_directories(kOutput);
    const fs::path scene = kOutput / (name + ".json");
    std::ofstream(scene) << scene_json;
    return scene;
}

// `envshadow render` (rasteriser) or `envshadow reference` of `scene` at 64 x 64 with `flags`, to OUTPUT.exr,
// both sampling each pixel at its centre.
fs::path render_with(const std::string& command, const fs::path& scene, const std::string& output,
                     const std::string& flags = "") {
    const fs::path exr = kOutput / (output + ".exr");
    const std::string common = "--scene '" + scene.string() + "' --width 64 --height 64 " + flags;
    if (command == "render")
        // One sample per pixel, at its centre, as the reference's one ray per pixel.
        run("render " + common + " --lights 64 --tile 128 --msaa 1 --backend egl --exr '" + exr.string() + "'",
            kOutput / (output + ".log"));
    else
        run("reference " + common + " --seed 7 --pixel-filter point --exr '" + exr.string() + "'",
            kOutput / (output + ".log"));
    return exr;
}

// The rasteriser's picture against the reference's, over the pixels both call object pixels.
Agreement compare(const fs::path& raster, const fs::path& reference) {
    Agreement result;
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

// Renders `scene_json` with both renderers and compares the linear EXRs.
Agreement render_both(const std::string& name, const std::string& scene_json) {
    const fs::path scene = write_scene(name, scene_json);
    const fs::path raster = render_with("render", scene, name + "_raster");
    const fs::path reference = render_with("reference", scene, name + "_reference");
    return compare(raster, reference);
}

constexpr const char* kPlaneUnderSky = R"({"environment": "builtin:sky",
        "camera": {"position": [0, 2.5, 2.5], "target": [0, 0, 0], "fov": 45},
        "objects": [{"name": "ground", "mesh": {"type": "plane", "size": 4}, "material": {"diffuse": 0.5}}]})";

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
    const Agreement agreement = render_both("plane", kPlaneUnderSky);
    ASSERT_GT(agreement.object_pixels, 2500);
    EXPECT_LT(agreement.mask_disagreements, 64 * 64 / 100) << "the two renderers do not share the camera";
    EXPECT_LT(agreement.relative_rmse, 0.02);
    EXPECT_NEAR(agreement.mean_ratio, 1.0, 0.01);
}

// --time moves builtin:sky's sun (one hour per second) in both renderers alike: the reference of the
// plane at 15 h agrees with the rasteriser's picture at 15 h, and is far from its picture at noon (the
// sun 11 degrees lower: about 30% less light), so the agreement is no accident of a sky that ignores time.
TEST(RasterAgreesWithReference, TheSkyAtATime) {
    const fs::path scene = write_scene("plane_at_time", kPlaneUnderSky);
    const fs::path reference = render_with("reference", scene, "plane_at_3_reference", "--time 3 --error 0.01");
    const Agreement same_time = compare(render_with("render", scene, "plane_at_3_raster", "--time 3"), reference);
    ASSERT_GT(same_time.object_pixels, 2500);
    EXPECT_LT(same_time.relative_rmse, 0.02);
    EXPECT_NEAR(same_time.mean_ratio, 1.0, 0.02);
    const Agreement noon = compare(render_with("render", scene, "plane_at_0_raster"), reference);
    EXPECT_GT(noon.relative_rmse, 0.15) << "the sky at noon and at 15 h light the plane alike";
}

// The mean RGB of the object pixels left (x < width / 2) or right of the middle.
glm::dvec3 mean_of_half(const Image& image, bool left) {
    glm::dvec3 sum(0.0);
    int count = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = left ? 0 : image.width / 2; x < (left ? image.width / 2 : image.width); ++x)
            if (image.at(x, y).a >= 1.0f) {
                sum += glm::dvec3(image.at(x, y));
                ++count;
            }
    EXPECT_GT(count, 200) << (left ? "left" : "right");
    return count > 0 ? sum / double(count) : sum;
}

// One glTF mesh, two primitives: a red quad left of x = 0 and a green one right of it, facing the
// camera, each with its own material (rough dielectrics). Under builtin:constant (radiance 1) a
// facing quad reflects rho_d = 0.96 base plus the specular albedo, at most F0 = 0.04. Both renderers draw
// glTF's BRDF: the rasteriser in ratio shading (cells shading's Phong stand-in misses its Fresnel and
// multiple-scattering loss: 5.8% off).
TEST(RasterAgreesWithReference, AModelOfTwoMaterialsShowsBothColours) {
    fs::create_directories(kOutput);
    test::GltfWriter w;
    const auto quad = [&](float x0, float x1) {
        return w.vec3s({{x0, -0.5f, 0.0f}, {x1, -0.5f, 0.0f}, {x1, 0.5f, 0.0f}, {x0, 0.5f, 0.0f}});
    };
    const int mesh = w.mesh(quad(-1.1f, -0.1f), w.indices({0, 1, 2, 0, 2, 3}));
    nlohmann::json green = w.doc["meshes"][mesh]["primitives"][0];
    green["attributes"]["POSITION"] = quad(0.1f, 1.1f);
    green["material"] = 1;
    w.doc["meshes"][mesh]["primitives"][0]["material"] = 0;
    w.doc["meshes"][mesh]["primitives"].push_back(green);
    const auto rough = [](double r, double g, double b) {
        return nlohmann::json{{"pbrMetallicRoughness", {{"baseColorFactor", {r, g, b, 1.0}}, {"metallicFactor", 0.0}}}};
    };
    w.doc["materials"] = nlohmann::json::array({rough(0.8, 0.1, 0.1), rough(0.1, 0.8, 0.1)});
    w.scene({w.node({{"mesh", mesh}})});
    const fs::path model = w.write(kOutput, "two_materials");
    const fs::path scene = write_scene("two_materials", R"({"environment": "builtin:constant",
        "camera": {"position": [0, 0, 3], "target": [0, 0, 0], "fov": 45},
        "objects": [{"model": ")" + model.string() + R"("}]})");
    const fs::path raster = render_with("render", scene, "two_materials_raster", "--shading ratio");
    const fs::path reference = render_with("reference", scene, "two_materials_reference");
    ASSERT_FALSE(HasFatalFailure());
    for (const fs::path& exr : {raster, reference}) {
        SCOPED_TRACE(exr.string());
        const Image image = read_exr(exr).image;
        const glm::dvec3 left = mean_of_half(image, true), right = mean_of_half(image, false);
        for (int c = 0; c < 3; ++c) {  // 0.96 * 0.8 or 0.96 * 0.1, plus 0 ... 0.04 of specular
            const double base_left = c == 0 ? 0.768 : 0.096, base_right = c == 1 ? 0.768 : 0.096;
            EXPECT_GT(left[c], base_left - 0.01) << "left, channel " << c;
            EXPECT_LT(left[c], base_left + 0.05) << "left, channel " << c;
            EXPECT_GT(right[c], base_right - 0.01) << "right, channel " << c;
            EXPECT_LT(right[c], base_right + 0.05) << "right, channel " << c;
        }
    }
    const Agreement agreement = compare(raster, reference);
    EXPECT_LT(agreement.relative_rmse, 0.02);
}

// `render` at its default multisampling against `reference` at its default pixel filter (the mean over each
// pixel's square), nothing else passed but the scene, the size, N and the reference's error target, on a
// sphere against builtin:constant: alpha is the sphere's coverage of each pixel in both, the resolve's
// mean of 4 samples (a quarter apart) and the reference's estimate, so they agree within that quantisation
// everywhere, silhouette included; the point-sampled reference's alpha (0 or 1) does not.
TEST(RasterAgreesWithReference, DefaultSettingsAgreeOnCoverage) {
    const fs::path scene = write_scene("silhouette", R"({"environment": "builtin:constant",
        "camera": {"position": [0, 0.5, 3], "target": [0, 0, 0], "fov": 45},
        "objects": [{"name": "ball", "mesh": {"type": "sphere", "radius": 0.6, "segments": 64},
                     "material": {"diffuse": 0.7}}]})");
    const std::string size = " --width 64 --height 48";
    const auto output = [&](const std::string& name) { return kOutput / (name + ".exr"); };
    run("render --scene '" + scene.string() + "'" + size + " --lights 32 --backend egl --exr '" +
            output("silhouette_raster").string() + "'",
        kOutput / "silhouette_raster.log");
    for (const std::string filter : {"box", "point"})
        run("reference --scene '" + scene.string() + "'" + size + " --error 0.01 --pixel-filter " + filter +
                " --exr '" + output("silhouette_" + filter).string() + "'",
            kOutput / ("silhouette_" + filter + ".log"));
    ASSERT_FALSE(HasFatalFailure());
    const Image raster = read_exr(output("silhouette_raster")).image;
    const Image box = read_exr(output("silhouette_box")).image, point = read_exr(output("silhouette_point")).image;
    int partly_covered = 0, box_off = 0, point_off = 0;
    for (std::size_t i = 0; i < raster.pixels.size(); ++i) {
        partly_covered += raster.pixels[i].a > 0.0f && raster.pixels[i].a < 1.0f ? 1 : 0;
        box_off += std::abs(box.pixels[i].a - raster.pixels[i].a) > 0.3f ? 1 : 0;
        point_off += std::abs(point.pixels[i].a - raster.pixels[i].a) > 0.3f ? 1 : 0;
    }
    EXPECT_GT(partly_covered, 40);
    EXPECT_EQ(box_off, 0);
    EXPECT_GT(point_off, partly_covered / 4);
}

}  // namespace
}  // namespace envshadow
