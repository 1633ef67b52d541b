// Metallic-roughness textures (docs/SCENES.md "Textures"): a quad under the sky over a dark ground, its texture's
// quadrants of different G (roughness) and B (metalness), nearest-filtered and stored linear. Each quadrant of
// ratio shading with glTF's BRDF is the quad drawn with that quadrant's factors and no texture: each pixel reads
// the GGX levels about its own roughness, including one below the sharpest level (the map itself). The mid
// values would read 0.05 and 0.21 if decoded as sRGB, and swapped channels would swap metal and roughness. The
// setting and cells shading (the Phong stand-in) keep the factors; the reference reads the texture the same way.
#include <memory>
#include <string>

#include "gl_fixture.h"
#include "reference/reference.h"
#include "render/renderer.h"
#include "render_test_util.h"
#include "scene/gltf_material.h"

namespace envshadow::testing {
namespace {

using MetallicRoughnessTextureTest = GlTest;

constexpr int kSize = 64;
const char* const kSky = "builtin:sky:intensity=0";  // no sun: the lobe's width shows in the horizon's blur
const glm::vec3 kBase{0.9f, 0.6f, 0.3f};
constexpr float kRoughnessFactor = 0.8f;
constexpr float kMetallicFactor = 0.9f;

// G and B of each quadrant's texel (qx, qy from the top left); R is not read.
struct Texel {
    int g, b;
};
Texel texel(int qx, int qy) {
    const Texel t[2][2] = {{{255, 0}, {64, 255}}, {{128, 128}, {20, 255}}};  // [qx][qy]; 20 * 0.8 / 255 < 0.125
    return t[qx][qy];
}

std::shared_ptr<const TextureImage> parameters_image() {
    auto image = std::make_shared<TextureImage>();
    image->width = image->height = 2;
    for (int qy = 0; qy < 2; ++qy)
        for (int qx = 0; qx < 2; ++qx) {
            const Texel t = texel(qx, qy);
            image->rgba.insert(image->rgba.end(), {9, std::uint8_t(t.g), std::uint8_t(t.b), 255});
        }
    return image;
}

Material textured() {
    Material m = material_from_metallic_roughness({kBase, kMetallicFactor, kRoughnessFactor});
    m.metallic_roughness_texture = MaterialTexture{parameters_image(), TextureWrap::clamp_to_edge,
                                                   TextureWrap::clamp_to_edge, /*nearest=*/true, /*srgb=*/false};
    return m;
}

// The factors glTF gives quadrant (qx, qy): the material's times the texel's B and G.
Material quadrant_factors(int qx, int qy) {
    const Texel t = texel(qx, qy);
    return material_from_metallic_roughness(
        {kBase, kMetallicFactor * float(t.b) / 255.0f, kRoughnessFactor * float(t.g) / 255.0f});
}

Scene quad(const Material& material) {
    Scene scene = quad_facing_the_camera(material);
    scene.environment.source = kSky;
    return scene;
}

Image render(const Scene& scene, const render::RenderSettings& settings) {
    return render_scene(scene, settings, kSize, kSize, {.method = Method::lloyd, .lights = 16});
}

TEST_P(MetallicRoughnessTextureTest, EachPixelIsShadedWithItsTexelsParameters) {
    const render::RenderSettings settings = commands_defaults();
    const Image shaded = render(quad(textured()), settings);
    for (int qy = 0; qy < 2; ++qy)
        for (int qx = 0; qx < 2; ++qx) {
            const glm::vec3 expected = quadrant_centre(render(quad(quadrant_factors(qx, qy)), settings), qx, qy);
            const glm::vec3 actual = quadrant_centre(shaded, qx, qy);
            for (int ch = 0; ch < 3; ++ch)
                EXPECT_NEAR(actual[ch], expected[ch], 2e-3f * expected[ch] + 1e-5f)
                    << "quadrant " << qx << "," << qy << " channel " << ch;
        }
    // The quadrants differ: the texture matters here.
    EXPECT_GT(glm::length(quadrant_centre(shaded, 0, 0) - quadrant_centre(shaded, 1, 1)),
              0.2f * glm::length(quadrant_centre(shaded, 0, 0)));
    EXPECT_GT(glm::length(quadrant_centre(shaded, 1, 0) - quadrant_centre(shaded, 0, 1)),
              0.2f * glm::length(quadrant_centre(shaded, 1, 0)));
}

TEST_P(MetallicRoughnessTextureTest, SwitchedOffAndInCellsShadingTheFactorsAlone) {
    const Material factors = material_from_metallic_roughness({kBase, kMetallicFactor, kRoughnessFactor});
    render::RenderSettings off = commands_defaults();
    off.metallic_roughness_texture = false;
    const Image switched_off = render(quad(textured()), off);
    const Image plain = render(quad(factors), commands_defaults());
    const Image cells_textured = render(quad(textured()), {});
    const Image cells_plain = render(quad(factors), {});
    for (int qy = 0; qy < 2; ++qy)
        for (int qx = 0; qx < 2; ++qx)
            for (int ch = 0; ch < 3; ++ch) {
                EXPECT_NEAR(quadrant_centre(switched_off, qx, qy)[ch], quadrant_centre(plain, qx, qy)[ch], 1e-5f)
                    << "switched off: quadrant " << qx << "," << qy << " channel " << ch;
                EXPECT_NEAR(quadrant_centre(cells_textured, qx, qy)[ch], quadrant_centre(cells_plain, qx, qy)[ch],
                            1e-5f)
                    << "cells: quadrant " << qx << "," << qy << " channel " << ch;
            }
}

// The reference reads the same parameters: each quadrant as the quad with its factors traced alone, within
// the two estimates' noise, and the render within a few percent of it.
TEST_P(MetallicRoughnessTextureTest, TheReferenceReadsTheSameParameters) {
    constexpr double kTarget = 0.01;
    constexpr int kReferenceSize = 32;  // the quadrants' centres are what is compared
    const auto reference = [&](const Material& material) {
        return reference_image(quad(material), kReferenceSize, kReferenceSize, kTarget, reference::PixelFilter::box);
    };
    const Image truth = reference(textured());
    const Image raster = render_scene(quad(textured()), commands_defaults(), kReferenceSize, kReferenceSize,
                                      {.method = Method::lloyd, .lights = 16});
    for (int qy = 0; qy < 2; ++qy)
        for (int qx = 0; qx < 2; ++qx) {
            const std::string at = "quadrant " + std::to_string(qx) + "," + std::to_string(qy);
            const glm::vec3 alone = quadrant_centre(reference(quadrant_factors(qx, qy)), qx, qy);
            const glm::vec3 expected = quadrant_centre(truth, qx, qy);
            for (int ch = 0; ch < 3; ++ch) {
                EXPECT_NEAR(expected[ch], alone[ch], 4.0 * kTarget * alone[ch]) << at << " channel " << ch;
                EXPECT_NEAR(quadrant_centre(raster, qx, qy)[ch], expected[ch], 0.05 * expected[ch])
                    << "render, " << at << " channel " << ch;
            }
        }
}

ENVSHADOW_INSTANTIATE_GL_TEST(MetallicRoughnessTextureTest);

}  // namespace
}  // namespace envshadow::testing
