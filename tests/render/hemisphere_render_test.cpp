// Issue 14: with a ground plane only the upper hemisphere is decomposed, so every cell asked for is
// drawn (none hidden under the ground), by the CPU methods and by the GPU Floyd-Steinberg sampler.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include "env/cells.h"
#include "env/environment.h"
#include "env/latlong.h"
#include "gl_fixture.h"
#include "render/embedded_shaders.h"
#include "render/fs_sampler.h"
#include "render/renderer.h"
#include "scene/meshes.h"

namespace envshadow::testing {
namespace {

using HemisphereRenderTest = GlTest;

// A diffuse sphere standing on a 20 m ground (docs/accuracy/scenes/sphere_ground.json, smaller).
Scene sphere_on_ground() {
    Scene scene;
    scene.has_ground = true;
    auto add = [&](Mesh mesh, glm::vec3 position, bool casts) {
        Object object;
        object.mesh = std::make_shared<Mesh>(std::move(mesh));
        object.transform = glm::translate(glm::mat4(1.0f), position);
        object.material = {glm::vec3(0.7f), 0.0f, 1.0f};
        object.casts_shadows = casts;
        scene.objects.push_back(std::move(object));
    };
    add(make_mesh(PlaneShape{20.0f}), glm::vec3(0.0f), false);
    add(make_mesh(SphereShape{0.5f, 48}), glm::vec3(0.0f, 0.5f, 0.0f), true);
    return scene;
}

render::CameraView camera() {
    render::CameraView view;
    view.eye = {0.0f, 2.2f, 4.5f};
    view.view_from_world = glm::lookAt(view.eye, glm::vec3(0.0f, 0.45f, 0.0f), glm::vec3(0, 1, 0));
    view.clip_from_view = glm::perspective(glm::radians(35.0f), 80.0f / 60.0f, 0.1f, 50.0f);
    view.width = 80;
    view.height = 60;
    return view;
}

render::FrameStats draw(const Scene& scene, const std::vector<Cell>& cells) {
    render::Renderer renderer;
    renderer.set_scene(scene);
    renderer.set_lights(cells);
    return renderer.render(0.0, camera());
}

TEST_P(HemisphereRenderTest, EveryCellOfTheUpperHemisphereIsDrawnOnAGround) {
    const Scene scene = sphere_on_ground();
    for (const auto& [spec, lights] :
         {std::pair<std::string, int>{"/usr/share/blender/datafiles/studiolights/world/courtyard.exr", 128},
          {"builtin:sky", 64}}) {
        const EnvironmentMap map = load_environment(spec);
        const Decomposition upper =
            decompose(map, {.method = Method::lloyd, .lights = lights, .hemisphere = Hemisphere::upper});
        const render::FrameStats stats = draw(scene, upper.cells);
        EXPECT_EQ(stats.lights, lights) << spec;
        EXPECT_EQ(stats.lights_below_ground, 0) << spec;
        // The whole sphere's cells lose a good part of N under the ground (the check is still made).
        const render::FrameStats full = draw(scene, decompose(map, {.method = Method::lloyd, .lights = lights}).cells);
        EXPECT_GT(full.lights_below_ground, lights / 8) << spec;
        EXPECT_LT(full.lights, lights) << spec;
    }
}

// fs-gpu with a ground: every light above the horizon, their radiance summing (in luminance) to the
// upper hemisphere's importance, each cap m 2 pi / K; the scan stops at the horizon.
TEST_P(HemisphereRenderTest, GpuFloydSteinbergSamplesOnlyTheUpperHemisphere) {
    const EnvironmentMap map = load_environment("/usr/share/blender/datafiles/studiolights/world/courtyard.exr");
    double upper_luminance = 0.0;  // integral of lum(L) dw above the horizon, computed here
    for (int j = 0; j < map.height / 2; ++j)
        for (int i = 0; i < map.width; ++i)
            upper_luminance +=
                latlong::luminance(glm::dvec3(map.at(i, j))) * latlong::texel_solid_angle(j, map.width, map.height);
    render::Renderer renderer;
    renderer.set_environment(map);
    render::FsSampler sampler(render::embedded_shaders());
    for (int samples : {32, 128}) {
        sampler.sample(renderer.environment_texture(), {.samples = samples, .upper_hemisphere = true});
        const std::vector<Cell> lights = sampler.read_lights();
        const render::FsCounts counts = sampler.read_counts();
        EXPECT_EQ(counts.rows_scanned, std::uint32_t(sampler.importance_size().y / 2));
        EXPECT_NEAR(double(counts.importance_sum), upper_luminance, 1e-4 * upper_luminance);
        EXPECT_GE(int(counts.samples),
                  0.85 * samples);  // as on the whole sphere (tests/fs): the scan's end loses a few
        double luminance = 0.0, solid_angle = 0.0;
        int below = 0;
        for (const Cell& light : lights) {
            below += light.direction.y < 0.0f;
            luminance += latlong::luminance(glm::dvec3(light.radiance));
            solid_angle += light.solid_angle;
        }
        EXPECT_EQ(below, 0) << "M=" << samples;
        // Each of the K samples carries S / K: the lights sum to S, and their caps to 2 pi.
        EXPECT_NEAR(luminance, counts.importance_sum, 1e-3 * counts.importance_sum) << "M=" << samples;
        EXPECT_NEAR(solid_angle, 2.0 * std::numbers::pi, 1e-3) << "M=" << samples;
        Scene scene = sphere_on_ground();
        const render::FrameStats stats = draw(scene, lights);
        EXPECT_EQ(stats.lights_below_ground, 0);
        EXPECT_EQ(stats.lights, int(lights.size()));
    }
}

ENVSHADOW_INSTANTIATE_GL_TEST(HemisphereRenderTest);

}  // namespace
}  // namespace envshadow::testing
