// With a ground plane only the upper hemisphere is decomposed (docs/DESIGN.md §3.1), so every cell asked
// for is drawn (none hidden under the ground), by the CPU methods and by the GPU Floyd-Steinberg sampler.
#include <cmath>
#include <cstdio>
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
        // The lights are cells of the sampled hemisphere: they sum to S, and their solid angles to 2 pi.
        EXPECT_NEAR(luminance, counts.importance_sum, 1e-3 * counts.importance_sum) << "M=" << samples;
        EXPECT_NEAR(solid_angle, 2.0 * std::numbers::pi, 1e-3) << "M=" << samples;
        Scene scene = sphere_on_ground();
        const render::FrameStats stats = draw(scene, lights);
        EXPECT_EQ(stats.lights_below_ground, 0);
        EXPECT_EQ(stats.lights, int(lights.size()));
    }
}

// fs-gpu's lights (the CPU method's blocks, integrated over their cells) light the
// scene as the CPU method fs does, on a ground (upper hemisphere) and without one (the whole sphere).
// Measured 0.5% apart on assets/scenes/default.json at N = 64 (docs/FS_GPU.md).
TEST_P(HemisphereRenderTest, GpuFloydSteinbergLightsAsTheCpuMethodDoes) {
    const EnvironmentMap map = load_environment("/usr/share/blender/datafiles/studiolights/world/city.exr");
    for (bool ground : {true, false}) {
        Scene scene = sphere_on_ground();
        scene.has_ground = ground;
        const std::vector<Cell> cpu =
            decompose(map,
                      {.method = Method::fs, .lights = 64, .hemisphere = ground ? Hemisphere::upper : Hemisphere::full})
                .cells;
        render::Renderer renderer;
        renderer.set_scene(scene);
        renderer.set_environment(map);
        renderer.set_lights(cpu);
        renderer.render(0.0, camera());
        const Image expected = renderer.read_back();
        render::FsSampler sampler(render::embedded_shaders());
        sampler.sample(renderer.environment_texture(), {.samples = 64, .upper_hemisphere = ground});
        const std::vector<Cell> gpu = sampler.read_lights();
        EXPECT_GE(gpu.size(), 60u) << "ground " << ground;
        renderer.set_lights(gpu);
        renderer.render(0.0, camera());
        const Image image = renderer.read_back();
        double squared = 0.0, reference = 0.0;
        for (std::size_t p = 0; p < image.pixels.size(); ++p) {
            if (expected.pixels[p].a < 0.5f) continue;
            for (int c = 0; c < 3; ++c) {
                squared += std::pow(double(image.pixels[p][c]) - double(expected.pixels[p][c]), 2.0);
                reference += std::pow(double(expected.pixels[p][c]), 2.0);
            }
        }
        ASSERT_GT(reference, 0.0);
        std::printf("fs-gpu vs fs, %s: rel. RMSE %.4f, %zu lights\n", ground ? "ground" : "no ground",
                    std::sqrt(squared / reference), gpu.size());
        EXPECT_LT(std::sqrt(squared / reference), 0.03) << "ground " << ground;
    }
}

ENVSHADOW_INSTANTIATE_GL_TEST(HemisphereRenderTest);

}  // namespace
}  // namespace envshadow::testing
