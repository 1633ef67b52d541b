// `--method fs-gpu` end to end: the renderer lit by lights the GPU sampler makes from the renderer's own
// environment texture, every frame. A box on a ground plane under builtin:sky at 9 h and at 15 h: the
// ground beside the box away from the sun is in its shadow, towards the sun it is lit, and the shadow
// turns with the sun.
#include <memory>
#include <numbers>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include "env/environment.h"
#include "fs_reference.h"
#include "gl_fixture.h"
#include "render/embedded_shaders.h"
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

float luminance(const glm::vec4& c) {
    return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

TEST_P(FsRenderTest, BoxShadowFollowsBuiltinSkysSunWithLightsSampledOnTheGpu) {
    Scene scene;
    scene.has_ground = true;
    scene.objects.push_back(object(make_mesh(PlaneShape{8.0f}), glm::vec3(0.0f), false));
    scene.objects.push_back(object(make_mesh(BoxShape{glm::vec3(1.0f)}), glm::vec3(0.0f, 0.5f, 0.0f), true));
    render::Renderer renderer;
    renderer.set_scene(scene);  // environment rotation 0: map directions are world directions
    render::FsSampler sampler(render::embedded_shaders());

    render::CameraView view;  // from above, so the ground all around the box is in view
    view.eye = {0.0f, 6.0f, 0.5f};
    view.view_from_world = glm::lookAt(view.eye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
    view.clip_from_view = glm::perspective(glm::radians(40.0f), 1.0f, 0.1f, 50.0f);
    view.width = view.height = 160;

    // Ground 0.9 m from the box's centre, towards and away from the sun's horizontal direction.
    glm::vec3 away_at[2];
    for (int t = 0; t < 2; ++t) {
        SkyParameters sky;
        sky.time_hours = t == 0 ? 9.0 : 15.0;
        const glm::dvec3 sun = envshadow::sun_direction(sky);
        const glm::vec3 horizontal = glm::normalize(glm::vec3(float(sun.x), 0.0f, float(sun.z)));
        away_at[t] = -0.9f * horizontal;

        renderer.set_environment(load_environment("builtin:sky:width=512,time=" + std::to_string(sky.time_hours)));
        sampler.sample(renderer.environment_texture(), render::FsSampleRequest{64});
        renderer.set_lights(sampler.read_lights());
        renderer.render(0.0, view);
        const Image image = renderer.read_back();
        const glm::ivec2 towards = pixel_of(view, 0.9f * horizontal), away = pixel_of(view, away_at[t]);
        ASSERT_EQ(image.at(towards.x, towards.y).a, 1.0f);
        ASSERT_EQ(image.at(away.x, away.y).a, 1.0f);
        const float lit = luminance(image.at(towards.x, towards.y));
        EXPECT_LT(luminance(image.at(away.x, away.y)), 0.5f * lit) << sky.time_hours << " h";
        if (t == 1) {  // where the morning shadow fell is in the sun by the afternoon
            const glm::ivec2 morning_shadow = pixel_of(view, away_at[0]);
            EXPECT_GT(luminance(image.at(morning_shadow.x, morning_shadow.y)), 0.8f * lit);
        }
    }
    ASSERT_LT(glm::dot(away_at[0], away_at[1]), 0.0f);  // the sun turned by more than 90 degrees
}

ENVSHADOW_INSTANTIATE_GL_TEST(FsRenderTest);

}  // namespace
}  // namespace envshadow::testing
