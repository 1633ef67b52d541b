// The shadow cache (RenderSettings::shadow_cache, docs/DESIGN.md §5.11) against drawing every caster
// every frame: the same images over an animation, no atlas pass while nothing moves, and a fresh
// static layer after the lights, the settings or the scene change.
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include "env/cells.h"
#include "env/environment.h"
#include "gl_fixture.h"
#include "render/render_test_util.h"
#include "render/renderer.h"
#include "scene/meshes.h"

namespace envshadow::testing {
namespace {

using render::CameraView;
using render::FrameStats;
using render::Renderer;
using render::RenderSettings;

constexpr int kWidth = 128, kHeight = 96;

CameraView look_at(glm::vec3 eye, glm::vec3 target) {
    return testing::look_at(eye, target, kWidth, kHeight);
}

// PSNR (dB) of `a` against `reference` over the RGB of the reference's object pixels (alpha 1); the
// peak is the reference's largest value there.

Object object_at(Mesh mesh, glm::vec3 position, glm::vec3 albedo, bool casts = true) {
    Object object;
    object.mesh = std::make_shared<Mesh>(std::move(mesh));
    object.transform = glm::translate(glm::mat4(1.0f), position);
    object.material = {albedo, 0.1f, 30.0f};
    object.casts_shadows = casts;
    return object;
}

// Flyover in small: a figure standing on the ground, a sphere beside it and, if `flying`, a second
// sphere circling above them (a loop of 4 s), its shadow crossing the others.
Scene small_flyover(bool flying, glm::vec3 figure_at = glm::vec3(-0.2f, 0.0f, 0.0f)) {
    Scene scene;
    scene.has_ground = true;
    scene.objects.push_back(object_at(make_mesh(PlaneShape{10.0f}), glm::vec3(0.0f), glm::vec3(0.6f), false));
    scene.objects.push_back(object_at(make_mesh(FigureShape{1.5f, 3000}), figure_at, glm::vec3(0.6f, 0.5f, 0.4f)));
    scene.objects.push_back(object_at(make_mesh(SphereShape{0.3f, 32}), {0.8f, 0.3f, 0.5f}, glm::vec3(0.5f)));
    if (flying) {
        Object flyer = object_at(make_mesh(SphereShape{0.35f, 32}), glm::vec3(0.0f), {0.7f, 0.2f, 0.2f});
        flyer.transform = glm::mat4(1.0f);
        flyer.animation.kind = Animation::Kind::orbit;
        flyer.animation.radius = 1.2f;
        flyer.animation.height = 2.2f;
        flyer.animation.period = 4.0;
        scene.objects.push_back(flyer);
    }
    return scene;
}

std::vector<Cell> sky_cells() {
    return decompose(load_environment("builtin:sky"), DecomposeOptions{Method::lloyd, 24, 1}).cells;
}

bool has_pass(const FrameStats& stats, const char* name) {
    for (const gl::PassTime& pass : stats.passes)
        if (pass.pass == name) return true;
    return false;
}

// A renderer with the cache and one drawing every caster every frame, fed the same scene and lights.
struct CachedAndUncached {
    Renderer cached, uncached;
    CachedAndUncached(const Scene& scene, RenderSettings settings)
        : cached(settings), uncached([&] {
              settings.shadow_cache = false;
              return settings;
          }()) {
        for (Renderer* renderer : {&cached, &uncached}) {
            renderer->set_scene(scene);
            renderer->set_lights(sky_cells());
        }
    }
    // The cached frame's stats; both frames rendered, the PSNR of the cached one against the other's.
    FrameStats render(double time, const CameraView& view, double& psnr, Image* image = nullptr) {
        const FrameStats stats = cached.render(time, view);
        const Image a = cached.read_back();
        uncached.render(time, view);
        psnr = object_psnr(a, uncached.read_back());
        if (image) *image = a;
        return stats;
    }
};

// Fits over the whole loop: the tiles stay put while the flyer moves.
RenderSettings fitted_over_animation() {
    RenderSettings settings;
    settings.shadow_fit = render::ShadowFit::animation;
    return settings;
}

using ShadowCacheTest = GlTest;

// The bar: cached and uncached frames within 80 dB over the loop (the same depths, so in fact
// the same pixels). The first frame draws the atlas whole; the second keeps the static layer; from then
// on only the flying sphere is drawn, over the layer's copy.
TEST_P(ShadowCacheTest, CachedFramesEqualUncachedOnesOverAnAnimation) {
    CachedAndUncached pair(small_flyover(true), fitted_over_animation());
    const CameraView view = look_at({0.6f, 2.6f, 5.0f}, {0.0f, 0.8f, 0.0f});
    const std::vector<double> times = {0.0, 0.3, 0.9, 1.7, 2.6, 3.3, 5.1};
    std::vector<Image> frames;
    std::size_t first_triangles = 0;
    for (std::size_t i = 0; i < times.size(); ++i) {
        double psnr = 0.0;
        Image image;
        const FrameStats stats = pair.render(times[i], view, psnr, &image);
        frames.push_back(image);
        EXPECT_GT(psnr, 80.0) << "time " << times[i];
        EXPECT_EQ(stats.atlas_passes, 1) << "something moves: the atlas is drawn every frame";
        EXPECT_TRUE(has_pass(stats, "shadow atlas"));
        EXPECT_EQ(stats.static_layer_renders, i == 1 ? 1 : 0) << "time " << times[i];
        EXPECT_EQ(stats.moving_casters_drawn, i == 0 ? 0 : 1) << "time " << times[i];
        if (i == 0) first_triangles = stats.atlas_triangles;
        if (i >= 2) {
            EXPECT_LT(4 * stats.atlas_triangles, first_triangles) << "only the flyer's triangles";
        }
    }
    // The sphere and its shadow really move: the frames differ.
    EXPECT_LT(object_psnr(frames[2], frames[4]), 50.0);
}

// With fits to each frame's casters (the default) every tile changes whenever the sphere moves:
// nothing is kept, every frame is drawn whole, and the images are still the uncached ones.
TEST_P(ShadowCacheTest, PerFrameFitsDrawEveryFrameWhole) {
    CachedAndUncached pair(small_flyover(true), RenderSettings{});
    const CameraView view = look_at({0.6f, 2.6f, 5.0f}, {0.0f, 0.8f, 0.0f});
    for (double time : {0.0, 0.5, 1.0, 1.5}) {
        double psnr = 0.0;
        const FrameStats stats = pair.render(time, view, psnr);
        EXPECT_GT(psnr, 80.0) << "time " << time;
        EXPECT_EQ(stats.atlas_passes, 1);
        EXPECT_EQ(stats.static_layer_renders, 0) << "time " << time;
        EXPECT_EQ(stats.moving_casters_drawn, 0) << "time " << time;
    }
}

// The viewer's camera drag over a still scene: after the first frame no atlas pass at all, and the
// images are those of an atlas drawn every frame.
TEST_P(ShadowCacheTest, AStillSceneDrawsNoAtlasPassAfterTheFirstFrame) {
    CachedAndUncached pair(small_flyover(false), RenderSettings{});
    for (int frame = 0; frame < 5; ++frame) {
        const float angle = 0.35f * float(frame);
        const CameraView view = look_at({5.0f * std::sin(angle), 2.4f, 5.0f * std::cos(angle)}, {0.0f, 0.8f, 0.0f});
        double psnr = 0.0;
        const FrameStats stats = pair.render(0.5 * frame, view, psnr);
        EXPECT_GT(psnr, 80.0) << "frame " << frame;
        EXPECT_EQ(stats.atlas_passes, frame == 0 ? 1 : 0) << "frame " << frame;
        EXPECT_EQ(has_pass(stats, "shadow atlas"), frame == 0) << "frame " << frame;
        EXPECT_EQ(stats.static_layer_renders, 0);
        EXPECT_EQ(stats.moving_casters_drawn, 0);
        if (frame > 0) {
            EXPECT_EQ(stats.atlas_triangles, 0u);
        }
    }
}

// Lights, settings and the static geometry changed under a warm cache: the next frames are the
// uncached ones again (each change does change the image, so a stale layer would show).
TEST_P(ShadowCacheTest, ChangedLightsSettingsAndSceneRenewTheCache) {
    for (const bool flying : {false, true}) {
        SCOPED_TRACE(flying ? "with the flying sphere" : "still scene");
        // Uniform tiles: a turned environment moves the fits alone (the atlas texture stays).
        RenderSettings settings = fitted_over_animation();
        settings.tile_sizing = render::TileSizing::uniform;
        CachedAndUncached pair(small_flyover(flying), settings);
        const CameraView view = look_at({0.6f, 2.6f, 5.0f}, {0.0f, 0.8f, 0.0f});
        double time = 0.0;
        Image before;
        // Three frames after each change: the whole atlas, then (something moving) the new layer, then its copy.
        auto three_frames = [&](const char* after) {
            for (int frame = 0; frame < 3; ++frame) {
                double psnr = 0.0;
                Image image;
                const FrameStats stats = pair.render(time, view, psnr, &image);
                EXPECT_GT(psnr, 80.0) << after << ", frame " << frame;
                if (frame == 0) {
                    EXPECT_EQ(stats.atlas_passes, 1) << after;
                    if (!before.pixels.empty()) {
                        EXPECT_LT(object_psnr(before, image), 60.0) << after;
                    }
                }
                if (flying) {
                    EXPECT_EQ(stats.static_layer_renders, frame == 1 ? 1 : 0) << after << ", frame " << frame;
                }
                if (!flying) {
                    EXPECT_EQ(stats.atlas_passes, frame == 0 ? 1 : 0) << after << ", frame " << frame;
                }
                before = image;
                time += flying ? 0.0 : 0.25;  // the flyer held still: each change is all that differs
            }
        };
        three_frames("the first frames");
        for (Renderer* renderer : {&pair.cached, &pair.uncached}) renderer->set_environment_rotation(80.0f);
        three_frames("the environment turned");
        for (Renderer* renderer : {&pair.cached, &pair.uncached}) {
            RenderSettings smaller = renderer->settings();
            smaller.tile_size = 128;
            renderer->set_settings(smaller);
        }
        three_frames("smaller tiles");
        const Scene moved = small_flyover(flying, glm::vec3(0.4f, 0.0f, -0.3f));
        for (Renderer* renderer : {&pair.cached, &pair.uncached}) {
            renderer->set_scene(moved);
            renderer->set_environment_rotation(80.0f);
        }
        three_frames("the figure moved");
    }
}

// The viewer shades at one sample per pixel while the view moves and at --msaa's count once it is
// still (docs/DESIGN.md §5.10): changing the samples keeps the atlas (no pass) and gives the images of
// a renderer made with that count.
TEST_P(ShadowCacheTest, ChangingTheSamplesKeepsTheAtlasAndMatchesAFreshRenderer) {
    const Scene scene = small_flyover(false);
    auto made_with = [&](int samples) {
        RenderSettings settings;
        settings.msaa = samples;
        auto renderer = std::make_unique<Renderer>(settings);
        renderer->set_scene(scene);
        renderer->set_lights(sky_cells());
        return renderer;
    };
    const auto switching = made_with(4), one = made_with(1), four = made_with(4);
    const CameraView view = look_at({0.6f, 2.6f, 5.0f}, {0.0f, 0.8f, 0.0f});
    one->render(0.0, view);
    four->render(0.0, view);
    const Image one_image = one->read_back(), four_image = four->read_back();

    EXPECT_EQ(switching->render(0.0, view).atlas_passes, 1);
    EXPECT_GT(object_psnr(switching->read_back(), four_image), 80.0);
    for (int samples : {1, 4}) {
        RenderSettings settings = switching->settings();
        settings.msaa = samples;
        switching->set_settings(settings);
        EXPECT_EQ(switching->render(0.0, view).atlas_passes, 0) << samples << " sample(s)";
        EXPECT_GT(object_psnr(switching->read_back(), samples == 1 ? one_image : four_image), 80.0)
            << samples << " sample(s)";
    }
    if (four->samples() > 1) {  // where the context has multisampling, the two counts differ at the edges
        EXPECT_LT(object_psnr(one_image, four_image), 70.0);
    }
}

ENVSHADOW_INSTANTIATE_GL_TEST(ShadowCacheTest);

}  // namespace
}  // namespace envshadow::testing
