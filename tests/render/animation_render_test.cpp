// glTF animation in the rasteriser and the reference (docs/DESIGN.md §5.13): simple_skin.gltf (a strip
// bent by a two-joint skin) and AnimatedMorphCube (a cube squashed by morph targets) rendered at two
// times differ, and at each time the rasteriser's picture, shadows on the ground included, agrees with
// the reference of that time far better than with the reference of the other: the shadow atlas and the
// shading see the pose of the frame's time, as the ray tracer does.
#include <cmath>
#include <string>

#include "env/cells.h"
#include "env/environment.h"
#include "gl_fixture.h"
#include "reference/reference.h"
#include "render/frame_plan.h"
#include "render/render_test_util.h"
#include "render/renderer.h"

namespace envshadow::testing {
namespace {

using AnimationRenderTest = GlTest;

constexpr int kWidth = 64, kHeight = 48;
const std::string kModels = "/usr/share/assimp/models/glTF2/";

Image raster(const Scene& scene, const EnvironmentMap& map, double time) {
    render::RenderSettings settings;
    settings.msaa = 1;  // the reference traces one ray per pixel centre
    render::Renderer renderer(settings);
    renderer.set_scene(scene);
    renderer.set_environment(map);
    renderer.set_lights(decompose(map, {.method = Method::lloyd, .lights = 32}).cells);
    renderer.render(time, render::camera_view(scene, kWidth, kHeight, time));
    return renderer.read_back();
}

Image traced(const Scene& scene, const EnvironmentMap& map, double time) {
    reference::ReferenceOptions options;
    options.width = kWidth;
    options.height = kHeight;
    options.time = time;
    options.target_error = 0.03;
    options.pixel_filter = reference::PixelFilter::point;
    return reference::render_reference(scene, map, options).image;
}

// Pixels whose luminance differs by more than 5% of the brighter.
int changed_pixels(const Image& a, const Image& b) {
    int changed = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        const float la = a.pixels[i].r + a.pixels[i].g + a.pixels[i].b;
        const float lb = b.pixels[i].r + b.pixels[i].g + b.pixels[i].b;
        changed += std::abs(la - lb) > 0.05f * std::max(la, lb) ? 1 : 0;
    }
    return changed;
}

struct Case {
    const char* file;
    double early, late;
};

void expect_pose_followed(const Case& c) {
    SCOPED_TRACE(c.file);
    Scene scene = load_scene(kModels + c.file);
    scene.environment.source = "builtin:sky";
    const EnvironmentMap map = load_environment(scene.environment.source);
    const Image early = raster(scene, map, c.early), late = raster(scene, map, c.late);
    EXPECT_GT(changed_pixels(early, late), kWidth * kHeight / 50);
    const Image truth_early = traced(scene, map, c.early), truth_late = traced(scene, map, c.late);
    // Each frame is nearer the truth of its own time than of the other time's by a wide margin.
    const double own_early = object_psnr(early, truth_early), other_early = object_psnr(early, truth_late);
    const double own_late = object_psnr(late, truth_late), other_late = object_psnr(late, truth_early);
    EXPECT_GT(own_early, other_early + 6.0) << own_early << " vs " << other_early;
    EXPECT_GT(own_late, other_late + 6.0) << own_late << " vs " << other_late;
    EXPECT_GT(own_late, 25.0);
}

TEST_P(AnimationRenderTest, SkinnedStripFollowsItsPoseInShadingAndShadows) {
    expect_pose_followed({"simple_skin/simple_skin.gltf", 0.0, 1.5});
}

TEST_P(AnimationRenderTest, MorphedCubeFollowsItsWeights) {
    expect_pose_followed({"glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf", 0.0, 0.8});
}

ENVSHADOW_INSTANTIATE_GL_TEST(AnimationRenderTest);

}  // namespace
}  // namespace envshadow::testing
