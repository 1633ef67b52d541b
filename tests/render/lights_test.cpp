// Cells to world lights: the rotation, which lights may be skipped, and each light's neighbourhood.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "env/environment.h"
#include "env/orientation.h"
#include "render/lights.h"

namespace envshadow::render {
namespace {

Cell make_cell(glm::vec3 direction, glm::vec3 radiance) {
    Cell cell;
    cell.direction = glm::normalize(direction);
    cell.radiance = radiance;
    cell.solid_angle = 0.1f;
    cell.cos_radius = 0.98f;
    cell.cos_radius_weighted = 0.99f;
    return cell;
}

TEST(WorldFromMap, RotatesAboutYRightHanded) {
    const glm::vec3 x = world_direction_from_map({1, 0, 0}, 90.0f);
    EXPECT_NEAR(x.x, 0.0f, 1e-6f);
    EXPECT_NEAR(x.z, -1.0f, 1e-6f);  // +X turns towards -Z seen from above
    const glm::vec3 up = world_direction_from_map({0, 1, 0}, 37.0f);
    EXPECT_NEAR(up.y, 1.0f, 1e-6f);
    const glm::vec3 d = glm::normalize(glm::vec3(0.2f, 0.5f, -0.7f));
    const glm::vec3 back = map_from_world(123.0f) * (world_from_map(123.0f) * d);
    EXPECT_NEAR(glm::length(back - d), 0.0f, 1e-6f);
}

// The sun per pixel (docs/DESIGN.md §5.14) follows one light only where it stands out from the rest.
TEST(SunLight, IsTheBrightestOnlyWhereItStandsOut) {
    std::vector<LightRecord> lights(16);
    for (LightRecord& light : lights) light.radiance = glm::vec4(1.0f, 1.0f, 1.0f, 0.0f);
    EXPECT_EQ(sun_light(lights), -1);  // an even sky: none
    lights[5].radiance = glm::vec4(1.5f, 1.5f, 1.5f, 0.0f);
    EXPECT_EQ(sun_light(lights), -1);  // 1.5 / 16.5 of the light: short of two even shares (2 / 16)
    lights[5].radiance = glm::vec4(3.0f, 3.0f, 3.0f, 0.0f);
    EXPECT_EQ(sun_light(lights), 5);                          // 3 / 18
    lights[9].radiance = glm::vec4(0.0f, 10.0f, 0.0f, 0.0f);  // green counts by its luminance, 7.15
    EXPECT_EQ(sun_light(lights), 9);
    EXPECT_EQ(sun_light({}), -1);
    std::vector<LightRecord> dark(4);
    EXPECT_EQ(sun_light(dark), -1);
}

TEST(SelectLights, KeepsEverythingWhenNotSkipping) {
    const std::vector<Cell> cells = {make_cell({0, 1, 0}, glm::vec3(1)), make_cell({0, -1, 0}, glm::vec3(0))};
    const LightSelection s = select_lights(cells, world_from_map(0.0f), true, false);
    EXPECT_EQ(s.kept.size(), 2u);
    EXPECT_EQ(s.below_ground + s.negligible, 0);
}

TEST(SelectLights, DropsLightsUnderTheGroundOnlyWhenThereIsOne) {
    const std::vector<Cell> cells = {make_cell({0, 1, 0}, glm::vec3(1)), make_cell({1, -0.2f, 0}, glm::vec3(1)),
                                     make_cell({1, 0.1f, 0}, glm::vec3(1))};
    const LightSelection with_ground = select_lights(cells, world_from_map(0.0f), true, true);
    EXPECT_EQ(with_ground.kept.size(), 2u);
    EXPECT_EQ(with_ground.below_ground, 1);
    for (const WorldLight& l : with_ground.kept) EXPECT_GE(l.direction.y, 0.0f);
    EXPECT_EQ(select_lights(cells, world_from_map(0.0f), false, true).kept.size(), 3u);
}

TEST(SelectLights, DropsZeroAndNegligibleRadianceButNotDimSky) {
    std::vector<Cell> cells = {make_cell({0, 1, 0}, glm::vec3(1000.0f)), make_cell({1, 1, 0}, glm::vec3(0.0f)),
                               make_cell({0, 1, 1}, glm::vec3(1e-5f)), make_cell({1, 1, 1}, glm::vec3(0.05f))};
    const LightSelection s = select_lights(cells, world_from_map(0.0f), false, true);
    EXPECT_EQ(s.negligible, 2);  // the black cell and the one carrying 1e-8 of the total
    ASSERT_EQ(s.kept.size(), 2u);
    EXPECT_FLOAT_EQ(s.kept[0].radiance.r, 1000.0f);
    EXPECT_FLOAT_EQ(s.kept[1].radiance.r, 0.05f);  // 5e-5 of the total: kept
}

TEST(SelectLights, RotatesDirectionsAndKeepsBothCaps) {
    const std::vector<Cell> cells = {make_cell({1, 0.5f, 0}, glm::vec3(1))};
    const LightSelection s = select_lights(cells, world_from_map(90.0f), false, true);
    ASSERT_EQ(s.kept.size(), 1u);
    const glm::vec3 expected = glm::normalize(world_from_map(90.0f) * cells[0].direction);
    EXPECT_NEAR(glm::length(s.kept[0].direction - expected), 0.0f, 1e-6f);
    EXPECT_LT(s.kept[0].direction.z, -0.8f);
    EXPECT_FLOAT_EQ(s.kept[0].cos_radius, 0.98f);
    EXPECT_FLOAT_EQ(s.kept[0].cos_radius_weighted, 0.99f);
}

WorldLight cap_light(glm::vec3 direction, float radius_degrees) {
    return {glm::normalize(direction), glm::vec3(1.0f), std::cos(glm::radians(radius_degrees)), 1.0f};
}

bool in_neighbourhood(const LightNeighbourhood& neighbourhood, std::size_t j) {
    return (neighbourhood.lights[j / 32] >> (j % 32) & 1u) != 0;
}

TEST(LightNeighbourhoods, HoldTheLightAndTheLightsWithinReachOfTheirCaps) {
    // Caps of 10 degrees: neighbours while the centres are within 2 (10 + 10) = 40 degrees.
    const float degree = std::numbers::pi_v<float> / 180.0f;
    const std::vector<WorldLight> lights = {
        cap_light({0, 1, 0}, 10.0f), cap_light({std::sin(35 * degree), std::cos(35 * degree), 0}, 10.0f),
        cap_light({0, std::cos(45 * degree), std::sin(45 * degree)}, 10.0f), cap_light({0, -1, 0}, 10.0f)};
    const std::vector<LightNeighbourhood> n = light_neighbourhoods(lights);
    ASSERT_EQ(n.size(), lights.size());
    for (std::size_t i = 0; i < lights.size(); ++i) {
        EXPECT_TRUE(in_neighbourhood(n[i], i));
        EXPECT_FALSE(n[i].surrounded);  // one neighbour at most
    }
    EXPECT_TRUE(in_neighbourhood(n[0], 1));
    EXPECT_TRUE(in_neighbourhood(n[1], 0));
    EXPECT_FALSE(in_neighbourhood(n[0], 2));
    EXPECT_FALSE(in_neighbourhood(n[0], 3));
    EXPECT_FALSE(in_neighbourhood(n[1], 2));  // 55 degrees apart
}

TEST(LightNeighbourhoods, ALoneLightIsNotSurrounded) {
    const std::vector<WorldLight> one = {cap_light({0.3f, 1, 0}, 5.0f)};
    const std::vector<LightNeighbourhood> n = light_neighbourhoods(one);
    ASSERT_EQ(n.size(), 1u);
    EXPECT_FALSE(n[0].surrounded);
}

// What the soft shadows' bound relies on: around every cell of a decomposition of the whole sphere, its
// neighbours' centres leave no gap wider than 120 degrees (a hexagonal ring leaves 60), and they are the
// first two rings at most (6 + 12), not the whole sky. Of the upper hemisphere's, the horizon closes the
// gap below the cells along it.
TEST(LightNeighbourhoods, SurroundEveryCellOfALloydDecomposition) {
    const EnvironmentMap sky = load_environment("builtin:sky:elevation=40");
    for (const Hemisphere hemisphere : {Hemisphere::full, Hemisphere::upper})
        for (const int n : {32, 128}) {
            const Decomposition d = decompose(sky, {Method::lloyd, n, 1, SiteSearch::tiles, hemisphere});
            const std::vector<WorldLight> lights = select_lights(d.cells, world_from_map(0.0f), false, false).kept;
            const std::vector<LightNeighbourhood> neighbourhoods = light_neighbourhoods(lights);
            ASSERT_EQ(neighbourhoods.size(), lights.size());
            for (std::size_t i = 0; i < lights.size(); ++i) {
                int count = 0;
                for (std::size_t j = 0; j < lights.size(); ++j) {
                    EXPECT_EQ(in_neighbourhood(neighbourhoods[i], j), in_neighbourhood(neighbourhoods[j], i));
                    if (j != i && in_neighbourhood(neighbourhoods[i], j)) ++count;
                }
                EXPECT_TRUE(neighbourhoods[i].surrounded)
                    << "N = " << n << ", light " << i << ", hemisphere " << int(hemisphere);
                EXPECT_GE(count, hemisphere == Hemisphere::full ? 3 : 2) << "N = " << n << ", light " << i;
                EXPECT_LE(count, 18) << "N = " << n << ", light " << i;
            }
        }
}

TEST(LightNeighbourhoods, RefuseMoreLightsThanTheBitSetsHold) {
    const std::vector<WorldLight> lights(std::size_t(kMaxLights) + 1, cap_light({0, 1, 0}, 1.0f));
    EXPECT_THROW(light_neighbourhoods(lights), std::invalid_argument);
}

}  // namespace
}  // namespace envshadow::render
