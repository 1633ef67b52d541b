// Alpha BLEND (docs/SCENES.md "Alpha"): a half-transparent card over a ground under a sky with a sun.
// - Over what is behind: with its shadow off, the blended card's image is the mean of the image with the card
//   opaque and the image without it (alpha 0.5), everywhere, its edges included.
// - Its shadow: on the ground beside the card, the light the blended card takes away is about half what the
//   opaque card takes away (the atlas's translucent layer; stochastic shadow rays in the reference); what lies
//   between it and the light (an opaque card above it) is not shadowed by it.
// - Order: two blended cards of different colours, one above the other, give the same image whichever comes
//   first in the scene (drawn back to front), and not the image of the wrong order.
// In the rasteriser at the engine's defaults, at the commands' defaults and without a depth pre-pass, and the
// first two in the reference.
#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "env/environment.h"
#include "gl_fixture.h"
#include "reference/reference.h"
#include "render/renderer.h"
#include "render_test_util.h"
#include "scene/meshes.h"

namespace envshadow::testing {
namespace {

using AlphaBlendTest = GlTest;

constexpr int kWidth = 96, kHeight = 72;

// A horizontal card at `height`, x and z from -0.5 to 0.5 shifted by `x`, facing up.
std::shared_ptr<Mesh> card(float height, float x) {
    auto mesh = std::make_shared<Mesh>();
    mesh->positions = {
        {x - 0.5f, height, 0.5f}, {x + 0.5f, height, 0.5f}, {x + 0.5f, height, -0.5f}, {x - 0.5f, height, -0.5f}};
    mesh->normals.assign(4, glm::vec3(0, 1, 0));
    mesh->texcoords = {{0.0f, 1.0f}, {1.0f, 1.0f}, {1.0f, 0.0f}, {0.0f, 0.0f}};
    mesh->indices = {0, 1, 2, 0, 2, 3};
    mesh->compute_bounds();
    return mesh;
}

Scene ground_under_sky() {
    Scene scene;
    scene.environment.source = "builtin:sky:elevation=40,azimuth=20,width=256";
    scene.has_ground = true;
    scene.camera.position = {0.3f, 1.7f, 1.5f};
    scene.camera.target = {-0.1f, 0.2f, -0.2f};
    scene.camera.fov_y_degrees = 60.0f;
    scene.objects.push_back(ground_plane());
    return scene;
}

Object card_object(float height, float x, glm::vec3 colour, AlphaMode mode, float alpha, bool casts_shadows) {
    Object object;
    object.mesh = card(height, x);
    object.material.rho_d = colour;
    object.material.alpha_mode = mode;
    object.material.base_alpha = alpha;
    object.casts_shadows = casts_shadows;
    return object;
}

enum class Card { none, opaque, blended };

Scene card_over_ground(Card kind, bool casts_shadows) {
    Scene scene = ground_under_sky();
    if (kind != Card::none)
        scene.objects.push_back(card_object(0.5f, 0.0f, glm::vec3(0.2f, 0.6f, 0.9f),
                                            kind == Card::blended ? AlphaMode::blend : AlphaMode::opaque,
                                            kind == Card::blended ? 0.5f : 1.0f, casts_shadows));
    return scene;
}

// A red card at 0.5 and a green one at 0.9, overlapping, both alpha 0.5 and blended; `red_first`: their order in
// the scene.
Scene two_cards(bool red_first) {
    Scene scene = ground_under_sky();
    Object red = card_object(0.5f, -0.2f, glm::vec3(0.9f, 0.1f, 0.1f), AlphaMode::blend, 0.5f, true);
    Object green = card_object(0.9f, 0.2f, glm::vec3(0.1f, 0.9f, 0.1f), AlphaMode::blend, 0.5f, true);
    if (!red_first) std::swap(red, green);
    scene.objects.push_back(std::move(red));
    scene.objects.push_back(std::move(green));
    return scene;
}

Image render_scene(const Scene& scene, const render::RenderSettings& settings) {
    return testing::render_scene(scene, settings, kWidth, kHeight,
                                 {.method = Method::lloyd, .lights = 32, .hemisphere = Hemisphere::upper});
}

Image reference_scene(const Scene& scene) {
    return reference_image(scene, kWidth, kHeight, 0.03);
}

double rgb_sum(const glm::vec4& p) {
    return double(p.r) + double(p.g) + double(p.b);
}

// Mean absolute difference of the RGB of `a` against the mean of `b` and `c`, relative to that mean's mean.
double difference_to_mean(const Image& a, const Image& b, const Image& c) {
    double difference = 0.0, mean = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            const double m = 0.5 * (double(b.pixels[i][k]) + double(c.pixels[i][k]));
            difference += std::abs(double(a.pixels[i][k]) - m);
            mean += m;
        }
    return difference / mean;
}

// The light taken from the ground by the card in `with` (against `without`), summed over the pixels where the
// card itself is not seen (`seen_card` differs from `without`).
double light_taken(const Image& with, const Image& without, const Image& seen_card) {
    double taken = 0.0;
    for (std::size_t i = 0; i < with.pixels.size(); ++i)
        if (std::abs(rgb_sum(seen_card.pixels[i]) - rgb_sum(without.pixels[i])) < 1e-4)
            taken += rgb_sum(without.pixels[i]) - rgb_sum(with.pixels[i]);
    return taken;
}

struct Images {
    Image none, opaque_unshadowed, blended_unshadowed, opaque, blended;
};

template <class Draw>
Images draw_cards(const Draw& draw) {
    return {draw(card_over_ground(Card::none, false)), draw(card_over_ground(Card::opaque, false)),
            draw(card_over_ground(Card::blended, false)), draw(card_over_ground(Card::opaque, true)),
            draw(card_over_ground(Card::blended, true))};
}

// `over_share`: how far the blended card may be from the mean of the opaque card and no card, as a share of the
// opaque card's own difference from no card (a card drawn opaque would be 0.5 away).
void expect_half_the_card(const Images& images, double over_share, double shadow_tolerance) {
    const double contrast = difference_to_mean(images.opaque_unshadowed, images.none, images.none);
    EXPECT_GT(contrast, 0.02) << "the card must be seen";
    EXPECT_LT(difference_to_mean(images.blended_unshadowed, images.opaque_unshadowed, images.none),
              over_share * contrast)
        << "the blended card against the mean of the opaque card and no card";
    const double opaque = light_taken(images.opaque, images.none, images.opaque_unshadowed);
    const double blended = light_taken(images.blended, images.none, images.opaque_unshadowed);
    EXPECT_GT(opaque, 0.0) << "the opaque card's shadow must be seen beside it";
    EXPECT_NEAR(blended / opaque, 0.5, shadow_tolerance) << "light taken by the blended card's shadow";
}

std::vector<std::pair<const char*, render::RenderSettings>> settings_cases() {
    render::RenderSettings no_prepass = commands_defaults();
    no_prepass.depth_prepass = false;
    return {{"engine defaults", {}}, {"commands' defaults", commands_defaults()}, {"no depth pre-pass", no_prepass}};
}

TEST_P(AlphaBlendTest, AHalfTransparentCardShowsAndCastsHalf) {
    for (const auto& [name, settings] : settings_cases()) {
        SCOPED_TRACE(name);
        // Measured: 3e-8 of the contrast, and 0.502-0.508 (the layer's 8 bits; the opaque card's penumbra is soft).
        expect_half_the_card(draw_cards([&](const Scene& s) { return render_scene(s, settings); }), 1e-4, 0.02);
    }
}

TEST_P(AlphaBlendTest, BlendedCardsAreDrawnBackToFront) {
    for (const auto& [name, settings] : settings_cases()) {
        SCOPED_TRACE(name);
        const Image red_first = render_scene(two_cards(true), settings);
        const Image green_first = render_scene(two_cards(false), settings);
        double largest = 0.0, total = 0.0;
        for (std::size_t i = 0; i < red_first.pixels.size(); ++i) {
            largest = std::max(largest, std::abs(rgb_sum(red_first.pixels[i]) - rgb_sum(green_first.pixels[i])));
            total += rgb_sum(red_first.pixels[i]);
        }
        EXPECT_LT(largest, 1e-5 * total / double(red_first.pixels.size()));
        // Where both cards cover the pixel, the green one (above, nearer the camera) lies over the red one: more
        // green than red.
        const Image& image = red_first;
        const glm::vec4 both = image.at(kWidth / 2, kHeight / 2 - 4);
        EXPECT_GT(both.g, both.r);
    }
}

// An opaque card above the blended one (nearer the sun) is lit as if the blended card cast nothing: only what
// lies behind a blended caster, seen from a cell, takes its transmittance.
TEST_P(AlphaBlendTest, WhatLiesBeforeABlendedCasterIsNotShadowedByIt) {
    const auto scene = [](bool upper, bool blended_casts) {
        Scene s = ground_under_sky();
        if (upper) s.objects.push_back(card_object(0.9f, 0.1f, glm::vec3(0.5f), AlphaMode::opaque, 1.0f, false));
        s.objects.push_back(
            card_object(0.5f, 0.0f, glm::vec3(0.2f, 0.6f, 0.9f), AlphaMode::blend, 0.5f, blended_casts));
        return s;
    };
    for (const auto& [name, settings] : settings_cases()) {
        SCOPED_TRACE(name);
        const Image without_upper = render_scene(scene(false, false), settings);
        const Image casting = render_scene(scene(true, true), settings);
        const Image not_casting = render_scene(scene(true, false), settings);
        // The upper card's pixels, those at its edges left out (their samples also see what lies behind it).
        const auto upper = [&](int x, int y) {
            const std::size_t i = std::size_t(y) * kWidth + std::size_t(x);
            return std::abs(rgb_sum(not_casting.pixels[i]) - rgb_sum(without_upper.pixels[i])) > 1e-3;
        };
        int upper_pixels = 0;
        double largest = 0.0;
        for (int y = 1; y + 1 < kHeight; ++y)
            for (int x = 1; x + 1 < kWidth; ++x) {
                bool inside = true;
                for (int k = 0; k < 9; ++k) inside = inside && upper(x + k % 3 - 1, y + k / 3 - 1);
                if (!inside) continue;
                ++upper_pixels;
                const glm::vec4 a = casting.at(x, y), b = not_casting.at(x, y);
                largest = std::max(largest, std::abs(rgb_sum(a) / rgb_sum(b) - 1.0));
            }
        EXPECT_GT(upper_pixels, 200);
        EXPECT_LT(largest, 2e-3);
    }
}

// The translucent layer under the shadow cache (docs/DESIGN.md §5.11, §5.15): over a still scene it is drawn once
// and kept, and the frames are those of a renderer that draws it every frame; a new alpha of the blended card
// (set_material) draws it again, and the frame is a fresh renderer's with that alpha.
TEST_P(AlphaBlendTest, AStillSceneKeepsItsTranslucentLayerUntilAnAlphaChanges) {
    const Scene scene = card_over_ground(Card::blended, true);
    const EnvironmentMap map = load_environment(scene.environment.source);
    const DecomposeOptions cells{.method = Method::lloyd, .lights = 32, .hemisphere = Hemisphere::upper};
    const render::CameraView view = render::camera_view(scene, kWidth, kHeight);
    const auto made = [&](bool cache, const Scene& with) {
        render::RenderSettings settings;
        settings.shadow_cache = cache;
        return prepared_renderer(with, map, settings, cells);
    };
    const auto translucent_passes = [](const render::FrameStats& stats) {
        return std::ranges::count_if(stats.passes,
                                     [](const gl::PassTime& pass) { return pass.pass == "translucent atlas"; });
    };
    const auto cached = made(true, scene), uncached = made(false, scene);
    for (int frame = 0; frame < 3; ++frame) {
        EXPECT_EQ(translucent_passes(cached->render(0.0, view)), frame == 0 ? 1 : 0) << "frame " << frame;
        EXPECT_EQ(translucent_passes(uncached->render(0.0, view)), 1) << "frame " << frame;
        EXPECT_GT(object_psnr(cached->read_back(), uncached->read_back()), 80.0) << "frame " << frame;
    }
    Scene clearer = scene;
    clearer.objects[1].material.base_alpha = 0.2f;
    const auto fresh = made(true, clearer);
    fresh->render(0.0, view);
    const Image expected = fresh->read_back();
    ASSERT_LT(object_psnr(cached->read_back(), expected), 60.0);  // the alpha shows, in the card and its shadow
    cached->set_material(1, clearer.objects[1].material);
    EXPECT_EQ(translucent_passes(cached->render(0.0, view)), 1);
    EXPECT_GT(object_psnr(cached->read_back(), expected), 80.0);
}

TEST(AlphaBlendReferenceTest, AHalfTransparentCardShowsAndCastsHalf) {
    expect_half_the_card(draw_cards(reference_scene), 0.35, 0.02);  // measured: 0.22 (its noise) and 0.500
}

// The box filter (the command's default) draws its camera rays all over the pixel, each stopping at the card
// with probability alpha; the point filter above draws a new salt per round for its one ray.
TEST(AlphaBlendReferenceTest, UnderTheBoxFilterTooTheCardShowsHalf) {
    const auto trace = [](Card kind) {
        return reference_image(card_over_ground(kind, false), kWidth, kHeight, 0.03, reference::PixelFilter::box);
    };
    const Image none = trace(Card::none), opaque = trace(Card::opaque);
    const double off = difference_to_mean(trace(Card::blended), opaque, none);
    const double contrast = difference_to_mean(opaque, none, none);    // the opaque card's own difference
    EXPECT_LT(off, 0.2 * contrast) << off << " against " << contrast;  // measured: 0.018 of it
}

ENVSHADOW_INSTANTIATE_GL_TEST(AlphaBlendTest);

}  // namespace
}  // namespace envshadow::testing
