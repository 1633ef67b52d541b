#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "viewer/orbit_camera.h"

namespace envshadow::app {
namespace {

void expect_near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-4f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

TEST(OrbitCamera, ResetReproducesTheSceneCamera) {
    Camera c;
    c.position = {3.0f, 2.0f, -4.0f};
    c.target = {0.5f, 0.25f, 1.0f};
    c.fov_y_degrees = 30.0f;
    const Camera back = OrbitCamera(c).camera();
    expect_near(back.position, c.position);
    expect_near(back.target, c.target);
    EXPECT_FLOAT_EQ(back.fov_y_degrees, 30.0f);
}

TEST(OrbitCamera, OrbitKeepsTheDistanceAndTheTarget) {
    Camera c;
    c.position = {0.0f, 1.0f, 5.0f};
    OrbitCamera orbit(c);
    const float before = glm::length(orbit.camera().position - orbit.camera().target);
    orbit.orbit(120.0f, -40.0f);
    const Camera after = orbit.camera();
    EXPECT_NEAR(glm::length(after.position - after.target), before, 1e-4f);
    expect_near(after.target, c.target);
    EXPECT_GT(glm::length(after.position - c.position), 0.5f);
}

TEST(OrbitCamera, PitchStopsShortOfThePole) {
    OrbitCamera orbit(Camera{});
    orbit.orbit(0.0f, 1e6f);
    const Camera c = orbit.camera();
    const glm::vec3 d = glm::normalize(c.position - c.target);
    EXPECT_LT(d.y, 0.999f);  // lookAt with +Y up stays defined
    EXPECT_GT(d.y, 0.99f);
}

TEST(OrbitCamera, PanMovesEyeAndTargetTogetherInTheImagePlane) {
    Camera c;
    c.position = {0.0f, 0.0f, 5.0f};
    c.target = {0.0f, 0.0f, 0.0f};
    OrbitCamera orbit(c);
    orbit.pan(-100.0f, 0.0f, 500.0f);  // drag left: the scene follows the mouse, so the camera moves right
    const Camera after = orbit.camera();
    expect_near(after.position - after.target, c.position - c.target);
    EXPECT_GT(after.target.x, 0.0f);  // looking along -Z, right is +X
    EXPECT_NEAR(after.target.y, 0.0f, 1e-5f);
    EXPECT_NEAR(after.target.z, 0.0f, 1e-5f);
}

TEST(OrbitCamera, ZoomScalesTheDistanceAndIsClamped) {
    Camera c;
    c.position = {0.0f, 0.0f, 10.0f};
    OrbitCamera orbit(c);
    orbit.zoom(1.0f);
    EXPECT_NEAR(orbit.distance(), 9.0f, 1e-4f);
    orbit.zoom(1000.0f);
    EXPECT_GE(orbit.distance(), 0.05f - 1e-6f);
}

}  // namespace
}  // namespace envshadow::app
