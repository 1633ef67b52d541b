// Base-colour textures in the rasteriser and the reference (docs/DESIGN.md §5.12): a quad whose 2x2
// nearest-filtered texture is red, green, blue and white, seen face on under a constant sky, shows each
// colour in the quadrant glTF's uv convention puts it (v = 0 at the image's top) in both renderers, and
// the two agree; a checkerboard finer than the pixels comes out as its mean in both (filtered, not
// point-sampled); the real BoxTextured model shows its texture's blue sky and green hill on the box where
// the untextured box is one colour; with textures switched off (RenderSettings::base_color_texture) the
// textured quad is the untextured one.
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "env/cells.h"
#include "env/environment.h"
#include "gl_fixture.h"
#include "reference/reference.h"
#include "render/frame_plan.h"
#include "render/renderer.h"
#include "render_test_util.h"
#include "scene/gltf.h"

namespace envshadow::testing {
namespace {

using TextureRenderTest = GlTest;

constexpr int kSize = 64;

// The quad in rho_d 0.8, its texture the four colours (nearest).
Scene textured_quad() {
    Material material;
    material.rho_d = glm::vec3(0.8f);
    material.base_color_texture =
        MaterialTexture{four_colours(), TextureWrap::clamp_to_edge, TextureWrap::clamp_to_edge, /*nearest=*/true};
    return quad_facing_the_camera(material);
}

// The colour of the quadrant (qx, qy in {0, 1}, from the top-left) at its centre, normalised by its sum.
glm::vec3 chromaticity(const Image& image, int qx, int qy) {
    const glm::vec4 p = image.at(image.width * (1 + 2 * qx) / 4, image.height * (1 + 2 * qy) / 4);
    const float sum = p.r + p.g + p.b;
    return sum > 0.0f ? glm::vec3(p) / sum : glm::vec3(0.0f);
}

void expect_four_colours(const Image& image) {
    const glm::vec3 red = chromaticity(image, 0, 0), green = chromaticity(image, 1, 0);
    const glm::vec3 blue = chromaticity(image, 0, 1), white = chromaticity(image, 1, 1);
    EXPECT_GT(red.r, 0.95f);
    EXPECT_GT(green.g, 0.95f);
    EXPECT_GT(blue.b, 0.95f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(white[c], 1.0f / 3.0f, 0.01f);
}

Image render_scene(const Scene& scene, int width, int height, const render::RenderSettings& settings = {}) {
    return testing::render_scene(scene, settings, width, height, {.method = Method::lloyd, .lights = 16});
}

TEST_P(TextureRenderTest, EachTexelLandsInItsQuadrantAsInTheReference) {
    const Scene scene = textured_quad();
    const Image raster = render_scene(scene, kSize, kSize);
    expect_four_colours(raster);

    reference::ReferenceOptions options;
    options.width = options.height = kSize;
    options.target_error = 0.02;
    options.pixel_filter = reference::PixelFilter::point;  // as the render, one sample per pixel
    const Image truth = reference::render_reference(scene, load_environment(scene.environment.source), options).image;
    expect_four_colours(truth);
    // Quadrant centres (away from the texel edges, where the GPU's mip chain and MSAA blend): equal within
    // the reference's noise. White under a unit sky: rho_d = 0.8 exactly.
    for (int qy = 0; qy < 2; ++qy)
        for (int qx = 0; qx < 2; ++qx) {
            const int x = kSize * (1 + 2 * qx) / 4, y = kSize * (1 + 2 * qy) / 4;
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(raster.at(x, y)[c], truth.at(x, y)[c], 0.03f)
                    << "quadrant " << qx << "," << qy << " channel " << c;
        }
    EXPECT_NEAR(raster.at(3 * kSize / 4, 3 * kSize / 4).g, 0.8f, 0.02f);
}

// RenderSettings::base_color_texture off: the textured quad is drawn as the same quad without its texture,
// bit for bit; on, it is not.
TEST_P(TextureRenderTest, TexturesSwitchedOffLeaveTheBaseColourFactor) {
    const Scene textured = textured_quad();
    Scene plain = textured;
    plain.objects[0].material.base_color_texture.reset();
    render::RenderSettings off;
    off.base_color_texture = false;
    const Image without = render_scene(plain, kSize, kSize);
    EXPECT_EQ(render_scene(textured, kSize, kSize, off).pixels, without.pixels);
    EXPECT_NE(render_scene(textured, kSize, kSize).pixels, without.pixels);
}

// Box pixels whose colour is clearly blue (the logo's sky) and clearly green (its hill).
struct Hues {
    int pixels = 0, blue = 0, green = 0;
};

Hues hues(const Image& image) {
    Hues h;
    for (const glm::vec4& p : image.pixels) {
        if (p.a < 1.0f) continue;
        ++h.pixels;
        h.blue += p.b > 1.5f * p.r && p.b > 1.1f * p.g ? 1 : 0;
        h.green += p.g > 1.5f * p.b && p.g > 1.2f * p.r ? 1 : 0;
    }
    return h;
}

TEST_P(TextureRenderTest, BoxTexturedShowsItsTextureAndWithoutItOneColour) {
    const GltfModel model = load_gltf("/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb");
    Scene scene;
    scene.environment.source = "builtin:constant";
    scene.camera = camera_framing(model.bounds_min, model.bounds_max);
    Object object;
    object.mesh = model.parts.at(0).mesh;
    object.material = model.parts.at(0).material;
    scene.objects.push_back(object);

    const Hues textured = hues(render_scene(scene, kSize, kSize));
    EXPECT_GT(textured.pixels, kSize * kSize / 8);
    EXPECT_GT(textured.blue, textured.pixels / 10) << textured.blue << " of " << textured.pixels;
    EXPECT_GT(textured.green, textured.pixels / 10) << textured.green << " of " << textured.pixels;

    scene.objects[0].material.base_color_texture.reset();
    const Hues plain = hues(render_scene(scene, kSize, kSize));
    EXPECT_EQ(plain.blue + plain.green, 0);
}

// A 256 x 256 checkerboard of black and white texels on the quad, 32 x 32 pixels: each pixel covers
// about 8 x 8 texels, so a pixel's value is the board's mean, half the white's linear value, not a
// black or white point sample. Both renderers filter: the GPU through the mip chain, the reference over
// the pixel's footprint (docs/DESIGN.md §5.12).
Scene minified_checkerboard() {
    Scene scene = textured_quad();
    auto image = std::make_shared<TextureImage>();
    image->width = image->height = 256;
    image->rgba.resize(256 * 256 * 4);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            for (int c = 0; c < 4; ++c)
                image->rgba[std::size_t(y * 256 + x) * 4 + std::size_t(c)] = (x + y) % 2 || c == 3 ? 255 : 0;
    scene.objects[0].material.base_color_texture = MaterialTexture{image};
    return scene;
}

// Mean and largest deviation from it of the green channel over the central half of the picture.
std::pair<double, double> centre_mean_and_spread(const Image& image) {
    double sum = 0.0, low = 1e30, high = -1e30;
    int n = 0;
    for (int y = image.height / 4; y < 3 * image.height / 4; ++y)
        for (int x = image.width / 4; x < 3 * image.width / 4; ++x) {
            const double g = image.at(x, y).g;
            sum += g;
            low = std::min(low, g);
            high = std::max(high, g);
            ++n;
        }
    const double mean = sum / n;
    return {mean, std::max(high - mean, mean - low)};
}

constexpr int kMinifiedSize = 32;
constexpr double kBoardMean = 0.8 * 0.5;  // rho_d times the mean of linear 0 and 1, under a unit sky

TEST_P(TextureRenderTest, AMinifiedCheckerboardRastersToItsMean) {
    const auto [mean, spread] =
        centre_mean_and_spread(render_scene(minified_checkerboard(), kMinifiedSize, kMinifiedSize));
    EXPECT_NEAR(mean, kBoardMean, 0.03 * kBoardMean);
    EXPECT_LT(spread, 0.1 * kBoardMean);
}

TEST(TextureReferenceTest, AMinifiedCheckerboardTracesToItsMean) {
    const Scene scene = minified_checkerboard();
    reference::ReferenceOptions options;
    options.width = options.height = kMinifiedSize;
    options.target_error = 0.01;
    options.pixel_filter = reference::PixelFilter::point;  // as the render, one sample per pixel
    const auto [mean, spread] = centre_mean_and_spread(
        reference::render_reference(scene, load_environment(scene.environment.source), options).image);
    EXPECT_NEAR(mean, kBoardMean, 0.03 * kBoardMean);
    EXPECT_LT(spread, 0.1 * kBoardMean);
}

ENVSHADOW_INSTANTIATE_GL_TEST(TextureRenderTest);

}  // namespace
}  // namespace envshadow::testing
