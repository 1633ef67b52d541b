// Cells to world lights: the rotation and which lights may be skipped.
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

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

}  // namespace
}  // namespace envshadow::render
