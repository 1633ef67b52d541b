// Emission (docs/SCENES.md "Emission"): a quad under a unit sky whose emission texture is red, green, blue and
// white (nearest-filtered) shows in each quadrant what it reflects plus the emission times that texel, worked
// out by hand. Every shading path adds it the same way (the paper's cells; ratio shading with the shadowed
// fraction at half rate and MSAA 4, the commands' defaults; glTF's BRDF), the fraction pass leaves it out
// (else the difference below would not be the emission alone), and the reference agrees.
#include <memory>
#include <utility>

#include "env/cells.h"
#include "env/environment.h"
#include "env/ggx_prefilter.h"
#include "env/prefilter.h"
#include "gl_fixture.h"
#include "reference/reference.h"
#include "render/frame_plan.h"
#include "render/renderer.h"
#include "render_test_util.h"
#include "scene/gltf_material.h"

namespace envshadow::testing {
namespace {

using EmissionTest = GlTest;

constexpr int kSize = 64;
const glm::vec3 kEmission{1.0f, 0.5f, 0.25f};

// `material` emitting kEmission times the four colours (nearest).
Material emissive(Material material) {
    material.emission = kEmission;
    material.emission_texture =
        MaterialTexture{four_colours(), TextureWrap::clamp_to_edge, TextureWrap::clamp_to_edge, /*nearest=*/true};
    return material;
}

// The quad, grey (rho_d = 0.5), emissive.
Scene emissive_quad() {
    Material material;
    material.rho_d = glm::vec3(0.5f);
    return quad_facing_the_camera(emissive(material));
}

Image render_scene(const Scene& scene, const render::RenderSettings& settings) {
    return testing::render_scene(scene, settings, kSize, kSize, {.method = Method::lloyd, .lights = 16});
}

// The texel of each quadrant (qx, qy from the top left), times kEmission.
glm::vec3 emitted(int qx, int qy) {
    const glm::vec3 texel[2][2] = {{{1, 0, 0}, {0, 0, 1}}, {{0, 1, 0}, {1, 1, 1}}};  // [qx][qy]
    return kEmission * texel[qx][qy];
}

TEST_P(EmissionTest, EachPathAddsTheEmissionTimesItsTexel) {
    const Material gltf = emissive(material_from_metallic_roughness({glm::vec3(0.5f), 0.0f, 0.6f}));
    for (const ShadingPath& c : shading_paths(emissive_quad().objects[0].material, gltf)) {
        SCOPED_TRACE(c.name);
        Material dark = c.material;
        dark.emission = glm::vec3(0.0f);
        const Image lit = render_scene(quad_facing_the_camera(c.material), c.settings),
                    reflected = render_scene(quad_facing_the_camera(dark), c.settings);
        for (int qy = 0; qy < 2; ++qy)
            for (int qx = 0; qx < 2; ++qx) {
                const glm::vec3 added = quadrant_centre(lit, qx, qy) - quadrant_centre(reflected, qx, qy);
                for (int ch = 0; ch < 3; ++ch)
                    EXPECT_NEAR(added[ch], emitted(qx, qy)[ch], 1e-3f)
                        << "quadrant " << qx << "," << qy << " channel " << ch;
            }
    }
}

// Grey 0.5 under a unit sky reflects 0.5; the emission adds on top, in both renderers.
TEST_P(EmissionTest, TheQuadShowsReflectionPlusEmissionAsTheReferenceDoes) {
    const Scene scene = emissive_quad();
    const Image raster = render_scene(scene, {});
    const Image truth = reference_image(scene, kSize, kSize, 0.02);
    for (int qy = 0; qy < 2; ++qy)
        for (int qx = 0; qx < 2; ++qx) {
            const glm::vec3 expected = glm::vec3(0.5f) + emitted(qx, qy);
            for (int ch = 0; ch < 3; ++ch) {
                EXPECT_NEAR(quadrant_centre(truth, qx, qy)[ch], expected[ch], 0.03f * expected[ch])
                    << "reference, quadrant " << qx << "," << qy << " channel " << ch;
                EXPECT_NEAR(quadrant_centre(raster, qx, qy)[ch], expected[ch], 0.03f * expected[ch])
                    << "render, quadrant " << qx << "," << qy << " channel " << ch;
            }
        }
}

ENVSHADOW_INSTANTIATE_GL_TEST(EmissionTest);

}  // namespace
}  // namespace envshadow::testing
