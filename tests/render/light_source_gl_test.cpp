// render::LightSource feeding a Renderer on a GL context: the GPU sampler's lights every frame, and the
// renderer's refusal of more lights than its atlas holds.
#include <algorithm>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>

#include "env/cells.h"
#include "env/environment.h"
#include "gl_fixture.h"
#include "render/light_source.h"
#include "render/renderer.h"

namespace envshadow::testing {
namespace {

using LightSourceTest = GlTest;

glm::vec3 brightest_direction(const std::vector<Cell>& lights) {
    const auto brightest = std::max_element(lights.begin(), lights.end(), [](const Cell& a, const Cell& b) {
        return a.radiance.r + a.radiance.g + a.radiance.b < b.radiance.r + b.radiance.g + b.radiance.b;
    });
    return brightest == lights.end() ? glm::vec3(0.0f) : brightest->direction;
}

// The per-frame source samples whatever map the renderer shows now: a new sky, a new sun.
TEST_P(LightSourceTest, TheGpuSamplerLightsTheRendererFromItsEnvironmentEveryFrame) {
    render::Renderer renderer;
    render::LightSource lights = render::make_light_source(render::light_method("fs-gpu"), EnvironmentMap{}, 32, 1);
    ASSERT_TRUE(lights.per_frame());
    ASSERT_NE(lights.sampler(), nullptr);
    lights.attach(renderer);  // nothing yet: the lights come with each frame
    EXPECT_EQ(renderer.light_count(), 0);
    for (double hours : {9.0, 15.0}) {
        renderer.set_environment(load_environment("builtin:sky:width=512,time=" + std::to_string(hours)));
        lights.update(renderer);
        EXPECT_EQ(lights.lights().size(), std::size_t(lights.sampler()->read_counts().light_count));
        EXPECT_GT(renderer.light_count(), 0);
        SkyParameters sky;
        sky.time_hours = hours;
        EXPECT_GT(glm::dot(glm::dvec3(brightest_direction(lights.lights())), sun_direction(sky)), 0.99) << hours;
    }
    EXPECT_EQ(lights.lights_folded(), 0);
}

TEST_P(LightSourceTest, TheRendererRefusesMoreLightsThanItHolds) {
    render::Renderer renderer;
    EXPECT_NO_THROW(renderer.set_lights(std::vector<Cell>(std::size_t(kMaxLights))));
    EXPECT_THROW(renderer.set_lights(std::vector<Cell>(std::size_t(kMaxLights) + 1)), std::invalid_argument);
}

ENVSHADOW_INSTANTIATE_GL_TEST(LightSourceTest);

}  // namespace
}  // namespace envshadow::testing
