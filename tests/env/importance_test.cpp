#include "env/importance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "env_test_data.h"

namespace envshadow {
namespace {

TEST(Importance, IsLuminanceTimesSolidAngle) {
    const EnvironmentMap& map = test::world("city");
    const ImportanceMap importance = build_importance(map);
    ASSERT_FALSE(importance.uniform_fallback);
    double total = 0.0;
    for (int j = 0; j < map.height; ++j) {
        const double dw = (2.0 * std::numbers::pi / map.width) * (std::cos(std::numbers::pi * j / map.height) -
                                                                  std::cos(std::numbers::pi * (j + 1) / map.height));
        for (int i = 0; i < map.width; ++i) {
            const glm::vec3 L = map.at(i, j);
            const double expected = (0.2126 * L.r + 0.7152 * L.g + 0.0722 * L.b) * dw;
            ASSERT_NEAR(importance.at(i, j), expected, 1e-6 * expected + 1e-30);
            total += expected;
        }
    }
    EXPECT_NEAR(importance.total, total, 1e-6 * total);
}

TEST(Importance, BrightestTexelSharesMatchTheDesignFigures) {
    // docs/DESIGN.md §7: the brightest texel holds 6.7% of the importance in city, 13.9% in sunrise, and
    // under 0.1% in courtyard and studio.
    for (const auto& [name, share, tolerance] :
         {std::tuple{"city", 0.067, 0.001}, std::tuple{"sunrise", 0.139, 0.001},
          std::tuple{"courtyard", 0.0005, 0.0005}, std::tuple{"studio", 0.0005, 0.0005}}) {
        const ImportanceMap importance = build_importance(test::world(name));
        float largest = 0.0f;
        for (float v : importance.importance) largest = std::max(largest, v);
        EXPECT_NEAR(largest / importance.total, share, tolerance) << name;
    }
}

TEST(Importance, BlackMapFallsBackToSolidAngle) {
    EnvironmentMap black = load_environment("builtin:constant:0");
    const ImportanceMap importance = build_importance(black);
    EXPECT_TRUE(importance.uniform_fallback);
    EXPECT_NEAR(importance.total, 4.0 * std::numbers::pi, 1e-4);
    for (int j = 0; j < black.height; ++j)
        ASSERT_NEAR(importance.at(5, j), importance.row_solid_angle[size_t(j)], 1e-7);
}

TEST(Importance, WhiteFurnaceIntegralIsFourPi) {
    const glm::dvec3 integral = integrate_radiance(load_environment("builtin:constant"));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(integral[c], 4.0 * std::numbers::pi, 1e-9);
}

TEST(Importance, IntegralOfARealMapMatchesTheDirectSum) {
    for (const std::string name : {"sunset", "night"}) {
        const EnvironmentMap& map = test::world(name);
        const glm::dvec3 expected = test::direct_integral(map), integral = integrate_radiance(map);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(integral[c], expected[c], 1e-9 * expected[c]) << name;
    }
}

}  // namespace
}  // namespace envshadow
