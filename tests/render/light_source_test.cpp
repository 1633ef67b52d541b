// The light-method table and the load-time side of render::LightSource (no GL).
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "env/cells.h"
#include "render/light_source.h"

namespace envshadow::render {
namespace {

TEST(LightMethods, EveryDecompositionThenTheGpuSamplerEachNamedOnce) {
    std::vector<std::string> names;
    for (const LightMethod& method : light_methods()) names.emplace_back(method.name());
    EXPECT_EQ(names, (std::vector<std::string>{"lloyd", "ccvt", "mediancut", "random", "fs", "fs-gpu"}));
    for (const LightMethod& method : light_methods()) {
        EXPECT_EQ(&light_method(method.name()), &method);
        EXPECT_EQ(&light_method(method.kind, method.decomposition), &method);
        EXPECT_FALSE(method.help.empty()) << method.name();
    }
    EXPECT_EQ(light_method("fs-gpu").kind, LightSourceKind::gpu_fs);
    EXPECT_EQ(light_method("fs").kind, LightSourceKind::cells);
    try {
        light_method("kmeans");
        ADD_FAILURE() << "no error";
    } catch (const UsageError& e) {
        EXPECT_EQ(std::string(e.what()), "unknown light method 'kmeans' (lloyd, ccvt, mediancut, random, fs, fs-gpu)");
    }
}

TEST(LightSource, CellsAreHandedOverAsDecomposed) {
    Decomposition d;
    d.method = Method::ccvt;
    d.cells.resize(3);
    d.cells[1].radiance = glm::vec3(2.0f);
    const LightSource source(d);
    EXPECT_FALSE(source.per_frame());
    EXPECT_EQ(source.kind(), LightSourceKind::cells);
    EXPECT_EQ(source.method().name(), "ccvt");
    EXPECT_EQ(source.sampler(), nullptr);
    ASSERT_EQ(source.lights().size(), 3u);
    EXPECT_EQ(source.lights()[1].radiance, glm::vec3(2.0f));
}

// More lights than the renderer holds: the brightest kMaxLights stay, scaled so that none of the
// radiance is lost.
TEST(LightSource, LightsBeyondTheLimitAreFoldedIntoTheBrightest) {
    std::vector<Cell> lights(std::size_t(kMaxLights) + 10);
    glm::dvec3 total(0.0);
    for (std::size_t i = 0; i < lights.size(); ++i) {
        lights[i].radiance = glm::vec3(float(i % 97) + 1.0f, 1.0f, 0.5f);
        lights[i].direction = glm::vec3(0.0f, 1.0f, 0.0f);
        total += glm::dvec3(lights[i].radiance);
    }
    std::vector<Cell> dimmest = lights;
    std::sort(dimmest.begin(), dimmest.end(), [](const Cell& a, const Cell& b) { return a.radiance.r < b.radiance.r; });
    const float dropped_below = dimmest[9].radiance.r;  // the 10 dimmest go (ties aside)

    EXPECT_EQ(fold_to_max_lights(lights), 10);
    ASSERT_EQ(lights.size(), std::size_t(kMaxLights));
    glm::dvec3 kept(0.0);
    float dimmest_kept = 1e30f;
    for (const Cell& c : lights) {
        kept += glm::dvec3(c.radiance);
        dimmest_kept = std::min(dimmest_kept, c.radiance.r);
    }
    for (int channel = 0; channel < 3; ++channel) EXPECT_NEAR(kept[channel] / total[channel], 1.0, 1e-5);
    EXPECT_GE(dimmest_kept, dropped_below);

    std::vector<Cell> few(5);
    EXPECT_EQ(fold_to_max_lights(few), 0);
    EXPECT_EQ(few.size(), 5u);
}

}  // namespace
}  // namespace envshadow::render
