// Occlusion textures (docs/SCENES.md "Occlusion"): a grey quad under a unit sky whose occlusion texture's R
// is 255, 128, 64 and 0 (nearest-filtered, stored linear) reflects 0.5 (1 + strength (R / 255 - 1)) in each
// quadrant, worked out by hand; the mid values would read 0.22 and 0.05 if the texture were decoded as sRGB.
// Every shading path multiplies the same way (the paper's cells; ratio shading with the shadowed fraction at
// half rate and MSAA 4, the commands' defaults; glTF's BRDF), the emission is left alone, the setting
// switches it off, and the reference agrees.
#include <memory>

#include "gl_fixture.h"
#include "reference/reference.h"
#include "render/renderer.h"
#include "render_test_util.h"
#include "scene/gltf_material.h"

namespace envshadow::testing {
namespace {

using OcclusionTest = GlTest;

constexpr int kSize = 64;
constexpr float kStrength = 0.8f;
const glm::vec3 kEmission{0.25f, 0.5f, 1.0f};

// R of the texel of each quadrant (qx, qy from the top left).
float occlusion_texel(int qx, int qy) {
    const float r[2][2] = {{1.0f, 64.0f / 255.0f}, {128.0f / 255.0f, 0.0f}};  // [qx][qy]
    return r[qx][qy];
}

std::shared_ptr<const TextureImage> occlusion_image() {
    auto image = std::make_shared<TextureImage>();
    image->width = image->height = 2;
    image->rgba = {255, 9, 9, 255, 128, 9, 9, 255,   // top row: R 255, 128 (G and B are not read)
                   64,  9, 9, 255, 0,   9, 9, 255};  // bottom row: R 64, 0
    return image;
}

// The occlusion factor glTF gives each quadrant.
float occlusion(int qx, int qy) {
    return 1.0f + kStrength * (occlusion_texel(qx, qy) - 1.0f);
}

Material with_occlusion(Material material) {
    material.occlusion_texture = MaterialTexture{occlusion_image(), TextureWrap::clamp_to_edge,
                                                 TextureWrap::clamp_to_edge, /*nearest=*/true, /*srgb=*/false};
    material.occlusion_strength = kStrength;
    return material;
}

Material grey() {
    Material material;
    material.rho_d = glm::vec3(0.5f);
    return material;
}

Image render_scene(const Scene& scene, const render::RenderSettings& settings) {
    return testing::render_scene(scene, settings, kSize, kSize, {.method = Method::lloyd, .lights = 16});
}

TEST_P(OcclusionTest, EachPathScalesTheReflectionAndNotTheEmission) {
    const Material gltf = material_from_metallic_roughness({glm::vec3(0.5f), 0.0f, 0.6f});
    for (const ShadingPath& c : shading_paths(grey(), gltf)) {
        SCOPED_TRACE(c.name);
        Material occluded = with_occlusion(c.material);
        occluded.emission = kEmission;
        Material open = c.material;
        open.emission = kEmission;
        const Image plain = render_scene(quad_facing_the_camera(open), c.settings);
        const Image shaded = render_scene(quad_facing_the_camera(occluded), c.settings);
        render::RenderSettings off = c.settings;
        off.occlusion_texture = false;
        const Image switched_off = render_scene(quad_facing_the_camera(occluded), off);
        for (int qy = 0; qy < 2; ++qy)
            for (int qx = 0; qx < 2; ++qx) {
                const glm::vec3 reflected = quadrant_centre(plain, qx, qy) - kEmission;
                const glm::vec3 expected = reflected * occlusion(qx, qy) + kEmission;
                for (int ch = 0; ch < 3; ++ch) {
                    EXPECT_NEAR(quadrant_centre(shaded, qx, qy)[ch], expected[ch], 2e-3f)
                        << "quadrant " << qx << "," << qy << " channel " << ch;
                    EXPECT_NEAR(quadrant_centre(switched_off, qx, qy)[ch], quadrant_centre(plain, qx, qy)[ch], 1e-4f)
                        << "switched off: quadrant " << qx << "," << qy << " channel " << ch;
                }
            }
    }
}

// Grey 0.5 under a unit sky reflects 0.5, times the occlusion, in both renderers.
TEST_P(OcclusionTest, TheQuadIsDarkenedAsTheReferenceDarkensIt) {
    const Scene scene = quad_facing_the_camera(with_occlusion(grey()));
    const Image raster = render_scene(scene, {});
    const Image truth = reference_image(scene, kSize, kSize, 0.02);
    for (int qy = 0; qy < 2; ++qy)
        for (int qx = 0; qx < 2; ++qx) {
            const float expected = 0.5f * occlusion(qx, qy);
            EXPECT_NEAR(quadrant_centre(truth, qx, qy).g, expected, 0.03f * expected)
                << "reference, quadrant " << qx << "," << qy;
            EXPECT_NEAR(quadrant_centre(raster, qx, qy).g, expected, 0.03f * expected)
                << "render, quadrant " << qx << "," << qy;
        }
}

ENVSHADOW_INSTANTIATE_GL_TEST(OcclusionTest);

}  // namespace
}  // namespace envshadow::testing
