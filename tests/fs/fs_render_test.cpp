// `--method fs-gpu` end to end: the renderer lit by lights the GPU sampler makes from the renderer's own
// environment texture, every frame. A box on a ground plane under a sky whose sun moves from +X to -X:
// the box's shadow must move to the other side.
// (builtin:sky's sun moves with --time once engine/env's loader is on main; until then the sky is the
// test's analytic one, with the sun placed directly.)
#include <memory>
#include <numbers>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include "fs_reference.h"
#include "gl_fixture.h"
#include "render/fs_sampler.h"
#include "render/renderer.h"
#include "scene/meshes.h"

namespace envshadow::testing {
namespace {

using FsRenderTest = GlTest;

Object object(Mesh mesh, glm::vec3 position, bool casts) {
    Object o;
    o.mesh = std::make_shared<const Mesh>(std::move(mesh));
    o.transform = glm::translate(glm::mat4(1.0f), position);
    o.material = Material{glm::vec3(0.8f), 0.0f, 1.0f};
    o.casts_shadows = casts;
    return o;
}

glm::ivec2 pixel_of(const render::CameraView& view, glm::vec3 p) {
    const glm::vec4 clip = view.clip_from_view * view.view_from_world * glm::vec4(p, 1.0f);
    const glm::vec2 ndc = glm::vec2(clip) / clip.w;
    return {int((ndc.x * 0.5f + 0.5f) * float(view.width)), int((0.5f - ndc.y * 0.5f) * float(view.height))};
}

float luminance(const glm::vec4& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

TEST_P(FsRenderTest, BoxShadowFollowsTheSunWithLightsSampledOnTheGpu) {
    Scene scene;
    scene.has_ground = true;
    scene.objects.push_back(object(make_mesh(PlaneShape{8.0f}), glm::vec3(0.0f), false));
    scene.objects.push_back(object(make_mesh(BoxShape{glm::vec3(1.0f)}), glm::vec3(0.0f, 0.5f, 0.0f), true));
    render::Renderer renderer;
    renderer.set_scene(scene);
    render::FsSampler sampler(project_shaders());

    render::CameraView view;
    view.eye = {0.0f, 4.0f, 4.0f};
    view.view_from_world = glm::lookAt(view.eye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
    view.clip_from_view = glm::perspective(glm::radians(40.0f), 192.0f / 128.0f, 0.1f, 50.0f);
    view.width = 192;
    view.height = 128;
    const glm::ivec2 east = pixel_of(view, {0.9f, 0.0f, 0.0f}), west = pixel_of(view, {-0.9f, 0.0f, 0.0f});

    // Morning: sun low in +X (azimuth 0); afternoon: low in -X (azimuth pi). Environment rotation 0:
    // map directions are world directions.
    float east_over_west[2] = {0.0f, 0.0f};
    const double azimuths[2] = {0.0, std::numbers::pi};
    for (int t = 0; t < 2; ++t) {
        renderer.set_environment(analytic_sky(256, sun_direction(0.5, azimuths[t]), 5000.0));
        sampler.sample(renderer.environment_texture(), render::FsSampleRequest{64});
        renderer.set_lights(sampler.read_lights());
        renderer.render(0.0, view);
        const Image image = renderer.read_back();
        ASSERT_EQ(image.at(east.x, east.y).a, 1.0f);
        ASSERT_EQ(image.at(west.x, west.y).a, 1.0f);
        east_over_west[t] = luminance(image.at(east.x, east.y)) / luminance(image.at(west.x, west.y));
    }
    EXPECT_GT(east_over_west[0], 2.0f);  // sun in the east: the shadow falls west of the box
    EXPECT_LT(east_over_west[1], 0.5f);  // sun in the west: it falls east
}

ENVSHADOW_INSTANTIATE_GL_TEST(FsRenderTest);

}  // namespace
}  // namespace envshadow::testing
