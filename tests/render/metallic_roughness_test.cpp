// glTF's metallic-roughness BRDF in ratio shading (docs/DESIGN.md §11): under a constant map with nothing to
// shadow, a sphere's pixel is the BRDF's directional albedo at its n.v, here computed by quadrature of
// gltf_brdf's lobes, not from the renderer's split-sum tables. That holds the GGX levels (1 under a constant
// map) and the DFG table's lookup in glsl/shade_metallic_roughness.glsl to the BRDF: coloured metals, and the
// Fresnel rise towards the rim that the Phong stand-in does not have.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "../brdf/ggx_quadrature.h"
#include "env/cells.h"
#include "env/environment.h"
#include "env/ggx_prefilter.h"
#include "env/gltf_brdf.h"
#include "env/prefilter.h"
#include "gl_fixture.h"
#include "reference/image_compare.h"
#include "reference/reference.h"
#include "render/frame_plan.h"
#include "render/renderer.h"
#include "render_test_util.h"
#include "scene/gltf_material.h"
#include "scene/meshes.h"

namespace envshadow::testing {
namespace {

using MetallicRoughnessTest = GlTest;

constexpr int kSize = 64;
constexpr float kRadius = 0.8f;

Scene sphere(const Material& material) {
    Scene scene;
    scene.environment.source = "builtin:constant";
    scene.camera.position = {0.0f, 0.0f, 3.0f};
    scene.camera.target = {0.0f, 0.0f, 0.0f};
    scene.camera.fov_y_degrees = 40.0f;
    Object object;
    object.mesh = std::make_shared<Mesh>(make_mesh(SphereShape{kRadius, 96}));
    object.transform = glm::mat4(1.0f);
    object.material = material;
    scene.objects.push_back(std::move(object));
    return scene;
}

Image render(const Scene& scene, const EnvironmentMap& map, render::ShadingMode shading, int lights = 8) {
    render::RenderSettings settings;
    settings.shading = shading;
    settings.msaa = 1;
    return render_scene(scene, map, settings, kSize, kSize, {.method = Method::lloyd, .lights = lights});
}

Image render(const Scene& scene, render::ShadingMode shading) {
    return render(scene, load_environment(scene.environment.source), shading);
}

// n.v where the ray through pixel (x, y)'s centre meets the analytic sphere (0 where it misses).
double n_dot_v_at(const Scene& scene, int x, int y) {
    const render::CameraView view = render::camera_view(scene, kSize, kSize);
    const glm::dmat4 world_from_clip = glm::inverse(glm::dmat4(view.clip_from_view * view.view_from_world));
    const glm::dvec4 far =
        world_from_clip * glm::dvec4((x + 0.5) / kSize * 2.0 - 1.0, (y + 0.5) / kSize * 2.0 - 1.0, 1.0, 1.0);
    const glm::dvec3 eye(view.eye), d = glm::normalize(glm::dvec3(far) / far.w - eye);
    const double b = glm::dot(eye, d), c = glm::dot(eye, eye) - double(kRadius) * kRadius;
    if (b * b - c < 0.0) return 0.0;
    const glm::dvec3 hit = eye + (-b - std::sqrt(b * b - c)) * d;
    return glm::dot(glm::normalize(hit), -d);
}

// The BRDF's directional albedo at n_dot_v, per channel: the diffuse lobe over directions, the specular one over
// GGX half vectors (dl = 4 v.h dh), both by tests/brdf/ggx_quadrature.h's midpoint rules.
glm::dvec3 albedo(const MetallicRoughness& m, double n_dot_v) {
    const gltf_brdf::MetallicRoughness p{glm::dvec3(m.base_color), m.metallic, m.roughness};
    const glm::dvec3 n(0.0, 0.0, 1.0), v = view_at(n_dot_v);
    const double alpha = gltf_brdf::alpha_from_roughness(p.roughness);
    glm::dvec3 result(0.0);
    for (int c = 0; c < 3; ++c) {
        result[c] = integral_over_hemisphere(
            200, [&](const glm::dvec3& l) { return gltf_brdf::evaluate_lobes(p, n, v, l).diffuse[c] * l.z; });
        result[c] += mean_over_ggx_half_vectors(alpha, 400, [&](const glm::dvec3& h) {
            const glm::dvec3 l = reflected(v, h);
            if (l.z <= 0.0 || glm::dot(v, h) <= 0.0) return 0.0;
            const double d = gltf_brdf::ggx_distribution(h.z, alpha);
            return gltf_brdf::evaluate_lobes(p, n, v, l).specular[c] * l.z * 4.0 * glm::dot(v, h) / (d * h.z);
        });
    }
    return result;
}

struct Case {
    std::string name;
    MetallicRoughness material;
};

// Every few pixels along the row through the sphere's centre, from the middle to n.v = 0.3: the render within 1%
// of the albedo (the DFG table's bilinear lookup and the tessellated sphere's normals; measured up to 0.4%).
TEST_P(MetallicRoughnessTest, WhiteFurnaceReturnsTheBrdfsAlbedo) {
    const std::vector<Case> cases = {
        {"white dielectric, rough", {glm::vec3(1.0f), 0.0f, 0.8f}},
        {"red dielectric", {glm::vec3(0.8f, 0.2f, 0.1f), 0.0f, 0.5f}},
        {"black dielectric", {glm::vec3(0.0f), 0.0f, 0.4f}},
        {"white metal", {glm::vec3(1.0f), 1.0f, 0.6f}},
        {"gold", {glm::vec3(1.0f, 0.78f, 0.34f), 1.0f, 0.4f}},
        {"half metal", {glm::vec3(0.5f, 0.6f, 0.9f), 0.5f, 0.7f}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const Scene scene = sphere(material_from_metallic_roughness(c.material));
        const Image image = render(scene, render::ShadingMode::ratio);
        int checked = 0;
        for (int x = kSize / 2; x < kSize; x += 3) {
            const int y = kSize / 2;
            const double n_dot_v = n_dot_v_at(scene, x, y);
            if (n_dot_v < 0.3) break;
            const glm::dvec3 expected = albedo(c.material, n_dot_v);
            const glm::vec4 pixel = image.at(x, y);
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(pixel[k], expected[k], 0.01 * std::max(expected[k], 0.02))
                    << "x " << x << " n.v " << n_dot_v << " channel " << k;
            ++checked;
        }
        EXPECT_GE(checked, 5);
    }
}

// Gold is gold (its F0 is its base colour) and a dielectric's reflection rises towards the rim (Schlick's
// Fresnel): neither holds for the Phong stand-in that cells shading draws, which reflects grey and evenly.
TEST_P(MetallicRoughnessTest, GoldReflectsGoldAndTheRimRises) {
    const Scene gold = sphere(material_from_metallic_roughness({glm::vec3(1.0f, 0.78f, 0.34f), 1.0f, 0.4f}));
    const glm::vec4 centre = render(gold, render::ShadingMode::ratio).at(kSize / 2, kSize / 2);
    EXPECT_GT(centre.r, 1.15f * centre.g);
    EXPECT_GT(centre.g, 1.5f * centre.b);
    const glm::vec4 stand_in = render(gold, render::ShadingMode::cells).at(kSize / 2, kSize / 2);
    EXPECT_LT(stand_in.r, 1.05f * stand_in.b);

    const Scene plastic = sphere(material_from_metallic_roughness({glm::vec3(0.0f), 0.0f, 0.4f}));
    const Image image = render(plastic, render::ShadingMode::ratio);
    int rim = kSize / 2;
    while (rim + 1 < kSize && n_dot_v_at(plastic, rim + 1, kSize / 2) > 0.25) ++rim;
    EXPECT_GT(image.at(rim, kSize / 2).g, 1.5f * image.at(kSize / 2, kSize / 2).g) << "rim at x " << rim;
}

// Relative RMSE over the pixels at least 3 pixels inside the silhouette in both images.
double inner_relative_rmse(const Image& image, const Image& truth) {
    double error2 = 0.0, reference2 = 0.0;
    int pixels = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            bool inside = true;
            for (int dy = -3; dy <= 3 && inside; ++dy)
                for (int dx = -3; dx <= 3; ++dx) {
                    const int u = std::clamp(x + dx, 0, kSize - 1), v = std::clamp(y + dy, 0, kSize - 1);
                    inside &= image.at(u, v).a >= 1.0f && truth.at(u, v).a >= 1.0f;
                }
            if (!inside) continue;
            ++pixels;
            const glm::vec4 r = image.at(x, y), t = truth.at(x, y);
            for (int c = 0; c < 3; ++c) {
                error2 += double(r[c] - t[c]) * double(r[c] - t[c]);
                reference2 += double(t[c]) * double(t[c]);
            }
        }
    EXPECT_GT(pixels, kSize * kSize / 5);
    return std::sqrt(error2 / reference2);
}

// Against the reference, which traces the same BRDF by importance sampling, under the sky without its sun
// (a bright sky over a dark ground: a sharp horizon). Nothing is shadowed, so the fraction is 1 and this is the
// split sum's own error (docs/DESIGN.md §11), measured over the inner pixels: a rough gold sphere 3.7%, most of
// it where the view grazes (the true lobe stretches, the prefiltered one stays round about r); a red dielectric
// 0.54%; a mirror-like metal (roughness 0.05, below the sharpest GGX level) 0.75%, blending that level with the
// map itself (about 5% reading the sharpest level alone, which blurs the horizon's reflection).
TEST_P(MetallicRoughnessTest, SpheresUnderTheSkyMatchTheReference) {
    const std::string spec = "builtin:sky:intensity=0";
    const EnvironmentMap map = load_environment(spec);
    struct Bounded {
        Case c;
        double bound;
    };
    const std::vector<Bounded> cases = {
        {{"gold, roughness 0.4", {glm::vec3(1.0f, 0.78f, 0.34f), 1.0f, 0.4f}}, 0.05},
        {{"red dielectric, roughness 0.5", {glm::vec3(0.8f, 0.2f, 0.1f), 0.0f, 0.5f}}, 0.01},
        {{"white metal, roughness 0.05", {glm::vec3(0.9f), 1.0f, 0.05f}}, 0.015},
    };
    for (const auto& [c, bound] : cases) {
        Scene scene = sphere(material_from_metallic_roughness(c.material));
        scene.environment.source = spec;
        reference::ReferenceOptions options;
        options.width = options.height = kSize;
        options.target_error = 0.002;
        options.pixel_filter = reference::PixelFilter::point;  // as the render, one sample per pixel
        const Image truth = reference::render_reference(scene, map, options).image;
        const double error = inner_relative_rmse(render(scene, map, render::ShadingMode::ratio), truth);
        std::printf("%s: relative RMSE %.4f over the inner pixels\n", c.name.c_str(), error);
        EXPECT_LT(error, bound) << c.name;
    }
}

// A sun's highlight on glossy gold, seen at n.v = 0.71 (the sun 90 degrees from the view): the split sum's lobe
// is round about r and its peak a factor n.v lower than the BRDF's. The sun is a compact source, whose
// reflection takes the lobe's true shape (docs/DESIGN.md §11). Measured over the inner pixels, 32 cells: 0.40%
// (28.7% with the split sum alone).
TEST_P(MetallicRoughnessTest, ASunsHighlightMatchesTheReference) {
    const std::string spec = "builtin:sky:azimuth=0";
    const EnvironmentMap map = load_environment(spec);
    Scene scene = sphere(material_from_metallic_roughness({glm::vec3(1.0f, 0.78f, 0.34f), 1.0f, 0.3f}));
    scene.environment.source = spec;
    reference::ReferenceOptions options;
    options.width = options.height = kSize;
    options.target_error = 0.002;
    options.pixel_filter = reference::PixelFilter::point;
    const Image truth = reference::render_reference(scene, map, options).image;
    const double error = inner_relative_rmse(render(scene, map, render::ShadingMode::ratio, 32), truth);
    std::printf("gold, roughness 0.3, under a sun: relative RMSE %.4f over the inner pixels\n", error);
    EXPECT_LT(error, 0.025);
}

// A smooth gold sphere (roughness 0.08) glinting the city's sun, at the commands' defaults: when a model of the
// sun's share was taken away from the split sum's lookup, the model exceeded what the lookup held at the glint's
// rim, and those pixels came out black (15 at 480 x 270). None may be far darker than the pixels about it
// (docs/DESIGN.md §11, *Compact sources*).
TEST_P(MetallicRoughnessTest, ASmoothMetalsGlintHasNoBlackPixels) {
    Scene scene = load_scene(std::string(ENVSHADOW_SOURCE_DIR) + "/assets/scenes/gold_sphere.json");
    scene.camera.position = {0.0f, 1.0f, 2.2f};
    scene.camera.target = {0.0f, 0.45f, 0.0f};
    int metals = 0;
    for (Object& o : scene.objects)
        if (o.material.metallic_roughness) {
            MetallicRoughness m = *o.material.metallic_roughness;
            m.roughness = 0.08f;
            o.material = with_metallic_roughness(o.material, m);
            ++metals;
        }
    ASSERT_EQ(metals, 1);
    constexpr int kWidth = 480, kHeight = 270;
    const Image image =
        render_scene(scene, commands_defaults(), kWidth, kHeight, {.method = Method::lloyd, .lights = 32});
    int black = 0;
    std::vector<float> around;
    for (int y = 2; y < kHeight - 2; ++y)
        for (int x = 2; x < kWidth - 2; ++x) {
            around.clear();
            for (int dy = -2; dy <= 2; ++dy)
                for (int dx = -2; dx <= 2; ++dx) around.push_back(image.at(x + dx, y + dy).r);
            std::nth_element(around.begin(), around.begin() + 12, around.end());
            if (around[12] > 1.0f && image.at(x, y).r < 0.02f * around[12]) ++black;
        }
    EXPECT_EQ(black, 0) << "pixels under 2% of the median about them";
}

// A smooth gold sphere (roughness 0.08) glinting the city's sun, at the commands' defaults (MSAA 4) against the
// box-filtered reference: the glint holds the sun's light once (the split sum's levels and mirror leave the sun
// out, env/compact_sources.h; it held 1.3x the reference's when the levels kept it) and in the pixels where the
// reference has it (the lobe averaged over each pixel about its centre). 128 x 96, 32 cells, whole image: 9.6%,
// 95% of it the glint's brightest pixel (63.5% with the sun left in the levels, the glint's 5 x 5 pixels 0.87 of
// the reference's light: more light than the reference's, spread wider).
TEST_P(MetallicRoughnessTest, ASmoothMetalsGlintHoldsTheSunOnceInItsPixels) {
    Scene scene = load_scene(std::string(ENVSHADOW_SOURCE_DIR) + "/assets/scenes/gold_sphere.json");
    scene.camera.position = {0.0f, 1.0f, 2.2f};
    scene.camera.target = {0.0f, 0.45f, 0.0f};
    for (Object& o : scene.objects)
        if (o.material.metallic_roughness) {
            MetallicRoughness m = *o.material.metallic_roughness;
            m.roughness = 0.08f;
            o.material = with_metallic_roughness(o.material, m);
        }
    constexpr int kWidth = 128, kHeight = 96;
    const EnvironmentMap map = load_environment(scene.environment.source);
    const Image image =
        render_scene(scene, map, commands_defaults(), kWidth, kHeight, {.method = Method::lloyd, .lights = 32});
    reference::ReferenceOptions options;
    options.width = kWidth;
    options.height = kHeight;
    options.target_error = 0.02;
    const Image truth = reference::render_reference(scene, map, options).image;
    // The glint: 5 x 5 pixels about the reference's brightest.
    int peak_x = 0, peak_y = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            if (truth.at(x, y).g > truth.at(peak_x, peak_y).g) peak_x = x, peak_y = y;
    double rendered = 0.0, expected = 0.0, rendered_ring = 0.0, expected_ring = 0.0;
    for (int y = peak_y - 2; y <= peak_y + 2; ++y)
        for (int x = peak_x - 2; x <= peak_x + 2; ++x) {
            rendered += image.at(x, y).g;
            expected += truth.at(x, y).g;
            if (std::max(std::abs(x - peak_x), std::abs(y - peak_y)) == 2) {
                rendered_ring += image.at(x, y).g;
                expected_ring += truth.at(x, y).g;
            }
        }
    const double error = reference::compare_images(truth, image).rel_rmse;
    std::printf(
        "gold, roughness 0.08: the glint's light %.3f of the reference's (%.3f two pixels out), relative RMSE "
        "%.4f\n",
        rendered / expected, rendered_ring / expected_ring, error);
    EXPECT_NEAR(rendered / expected, 1.0, 0.05);
    // Its tail two pixels out: 1.19 of the reference's while the lobe beyond the pixel grid was widened by the
    // footprint (docs/DESIGN.md §11, *Compact sources*), 1.05 taken at the pixel's centre unwidened.
    EXPECT_NEAR(rendered_ring / expected_ring, 1.0, 0.08);
    EXPECT_LT(error, 0.12);
}

// A smooth gold sphere's silhouette under a sun, at the commands' defaults (MSAA 4), against the box-filtered
// reference over the pixels the sphere partly covers. The sun's lobe is widened by the pixel's footprint; at a
// silhouette that is the normal's turn to grazing, where the visibility term at the sample's own n.v
// (1 / (2 alpha n.l) at n.v = 0), or at the pixel's centre carried past the silhouette, made a ring of sunlight
// round the sphere (docs/DESIGN.md §11, *Compact sources*): 339% over these pixels, 17.7% with the visibility
// and the cosine at the normal the glint lies at.
TEST_P(MetallicRoughnessTest, ASmoothMetalsSilhouetteHasNoRingOfSunlight) {
    const std::string spec = "builtin:sky:azimuth=0";
    const EnvironmentMap map = load_environment(spec);
    Scene scene = sphere(material_from_metallic_roughness({glm::vec3(1.0f, 0.78f, 0.34f), 1.0f, 0.1f}));
    scene.environment.source = spec;
    const Image image =
        render_scene(scene, map, commands_defaults(), kSize, kSize, {.method = Method::lloyd, .lights = 32});
    reference::ReferenceOptions options;
    options.width = options.height = kSize;
    options.target_error = 0.01;
    const Image truth = reference::render_reference(scene, map, options).image;
    double error2 = 0.0, reference2 = 0.0;
    int pixels = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const float coverage = truth.at(x, y).a;
            if (coverage <= 0.02f || coverage >= 0.98f) continue;
            ++pixels;
            for (int c = 0; c < 3; ++c) {
                const double e = double(image.at(x, y)[c]) - double(truth.at(x, y)[c]);
                error2 += e * e;
                reference2 += double(truth.at(x, y)[c]) * double(truth.at(x, y)[c]);
            }
        }
    ASSERT_GT(pixels, 100);
    const double error = std::sqrt(error2 / reference2);
    std::printf("gold, roughness 0.1, under a sun: relative RMSE %.4f over %d silhouette pixels\n", error, pixels);
    EXPECT_LT(error, 0.3);
}

ENVSHADOW_INSTANTIATE_GL_TEST(MetallicRoughnessTest);

}  // namespace
}  // namespace envshadow::testing
