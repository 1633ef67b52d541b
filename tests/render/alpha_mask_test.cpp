// Alpha MASK (docs/SCENES.md "Alpha"): a card whose alpha texture cuts away one half must look, shadow
// included, like a card that is only the other half. Under a sky with a sun, a horizontal card over a ground
// is drawn three ways: masked (its right texel's alpha 0), as its opaque left half alone (the geometry the
// mask should leave), and whole and opaque. In the rasteriser (at the engine's defaults, at the commands'
// defaults and without a depth pre-pass, where shade.frag cuts out itself) and in the reference, the masked
// card's image is the half card's within the edges' rasterisation and the reference's noise, and far from
// the whole card's: one sees the ground through the cut half, and light reaches the ground under it.
#include <cmath>
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
#include "scene/meshes.h"

namespace envshadow::testing {
namespace {

using AlphaMaskTest = GlTest;

constexpr int kWidth = 96, kHeight = 72;

// 2x1 texels, nearest: the left one opaque, the right one with alpha 0.
std::shared_ptr<const TextureImage> left_half_opaque() {
    auto image = std::make_shared<TextureImage>();
    image->width = 2;
    image->height = 1;
    image->rgba = {200, 200, 200, 255, 200, 200, 200, 0};
    return image;
}

// A horizontal card at height 0.5 from x0 to x1 (z from -0.5 to 0.5), facing up, u running along x over the
// whole card's width [-0.5, 0.5].
std::shared_ptr<Mesh> card(float x0, float x1) {
    auto mesh = std::make_shared<Mesh>();
    mesh->positions = {{x0, 0.5f, 0.5f}, {x1, 0.5f, 0.5f}, {x1, 0.5f, -0.5f}, {x0, 0.5f, -0.5f}};
    mesh->normals.assign(4, glm::vec3(0, 1, 0));
    mesh->texcoords = {{x0 + 0.5f, 1.0f}, {x1 + 0.5f, 1.0f}, {x1 + 0.5f, 0.0f}, {x0 + 0.5f, 0.0f}};
    mesh->indices = {0, 1, 2, 0, 2, 3};
    mesh->compute_bounds();
    return mesh;
}

enum class Card { masked, left_half, whole };

Scene card_over_ground(Card kind) {
    Scene scene;
    scene.environment.source = "builtin:sky:elevation=65,azimuth=20,width=256";
    scene.has_ground = true;
    scene.camera.position = {0.5f, 1.5f, 1.3f};
    scene.camera.target = {0.1f, 0.1f, -0.1f};
    scene.camera.fov_y_degrees = 60.0f;
    scene.objects.push_back(ground_plane());
    Object object;
    object.mesh = card(-0.5f, kind == Card::left_half ? 0.0f : 0.5f);
    object.material.rho_d = glm::vec3(0.6f);
    if (kind == Card::masked) {
        object.material.base_color_texture =
            MaterialTexture{left_half_opaque(), TextureWrap::clamp_to_edge, TextureWrap::clamp_to_edge, true};
        object.material.rho_d = glm::vec3(0.6f / std::pow(200.0f / 255.0f, 2.2f));  // about the same grey
        object.material.alpha_mode = AlphaMode::mask;
    }
    scene.objects.push_back(std::move(object));
    return scene;
}

Image render_scene(const Scene& scene, const render::RenderSettings& settings) {
    return testing::render_scene(scene, settings, kWidth, kHeight,
                                 {.method = Method::lloyd, .lights = 32, .hemisphere = Hemisphere::upper});
}

// Mean absolute difference of the RGB over the image, relative to b's mean. Masked and half card differ by
// 0.07-0.14% (edge pixels), masked and whole card by 3.5%.
double relative_difference(const Image& a, const Image& b) {
    double difference = 0.0, mean = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            difference += std::abs(double(a.pixels[i][c]) - double(b.pixels[i][c]));
            mean += double(b.pixels[i][c]);
        }
    return difference / mean;
}

void expect_masked_is_the_half_card(const Image& masked, const Image& half, const Image& whole, double tolerance) {
    const double to_half = relative_difference(masked, half), to_whole = relative_difference(masked, whole);
    EXPECT_LT(to_half, tolerance) << "masked against the half card";
    EXPECT_GT(to_whole, 4.0 * tolerance) << "masked against the whole card";
}

TEST_P(AlphaMaskTest, AMaskedCardLooksAndCastsLikeTheHalfItKeeps) {
    render::RenderSettings defaults;  // the commands' defaults
    defaults.shading = render::ShadingMode::ratio;
    defaults.shadows = render::ShadowMode::soft;
    defaults.shadow_rate = render::ShadowRate::half;
    defaults.msaa = 4;
    render::RenderSettings no_prepass = defaults;
    no_prepass.depth_prepass = false;
    const struct {
        const char* name;
        render::RenderSettings settings;
    } cases[] = {{"engine defaults", {}}, {"commands' defaults", defaults}, {"no depth pre-pass", no_prepass}};
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        expect_masked_is_the_half_card(render_scene(card_over_ground(Card::masked), c.settings),
                                       render_scene(card_over_ground(Card::left_half), c.settings),
                                       render_scene(card_over_ground(Card::whole), c.settings), 0.005);
    }
}

// The shadow cache keeps a still scene's atlas from frame to frame (docs/DESIGN.md §5.11); what cuts a masked
// caster is part of what it holds. Switching the base-colour textures off (the viewer's debug view) or making the
// card opaque by set_material must give the next frame of a fresh renderer with that setting or material: the
// whole card's shadow, not the half card's kept from the frame before.
TEST_P(AlphaMaskTest, TheCachedAtlasFollowsWhatCutsTheMaskedCaster) {
    const Scene scene = card_over_ground(Card::masked);
    const EnvironmentMap map = load_environment(scene.environment.source);
    const DecomposeOptions cells{.method = Method::lloyd, .lights = 32, .hemisphere = Hemisphere::upper};
    const render::CameraView view = render::camera_view(scene, kWidth, kHeight);
    const auto made = [&](const render::RenderSettings& settings, const Scene& with) {
        return prepared_renderer(with, map, settings, cells);
    };
    render::RenderSettings cached;
    ASSERT_TRUE(cached.shadow_cache);
    render::RenderSettings untextured = cached;
    untextured.base_color_texture = false;
    Scene opaque = scene;
    opaque.objects[1].material.alpha_mode = AlphaMode::opaque;
    const auto image_of = [&](const render::RenderSettings& settings, const Scene& with) {
        const auto renderer = made(settings, with);
        renderer->render(0.0, view);
        return renderer->read_back();
    };
    const Image masked = image_of(cached, scene);
    const Image without_textures = image_of(untextured, scene), made_opaque = image_of(cached, opaque);
    ASSERT_GT(relative_difference(masked, without_textures), 0.02);  // the cut half's shadow and its ground
    ASSERT_GT(relative_difference(masked, made_opaque), 0.02);

    const auto switching = made(cached, scene);
    switching->render(0.0, view);
    switching->set_settings(untextured);
    switching->render(0.0, view);
    EXPECT_LT(relative_difference(switching->read_back(), without_textures), 1e-5) << "textures off";
    switching->set_settings(cached);
    switching->render(0.0, view);
    EXPECT_LT(relative_difference(switching->read_back(), masked), 1e-5) << "textures on again";
    switching->set_material(1, opaque.objects[1].material);
    switching->render(0.0, view);
    EXPECT_LT(relative_difference(switching->read_back(), made_opaque), 1e-5) << "the card made opaque";
}

TEST(AlphaMaskReferenceTest, AMaskedCardLooksAndCastsLikeTheHalfItKeeps) {
    const auto trace = [](Card kind) { return reference_image(card_over_ground(kind), kWidth, kHeight, 0.03); };
    expect_masked_is_the_half_card(trace(Card::masked), trace(Card::left_half), trace(Card::whole), 0.005);
}

ENVSHADOW_INSTANTIATE_GL_TEST(AlphaMaskTest);

}  // namespace
}  // namespace envshadow::testing
