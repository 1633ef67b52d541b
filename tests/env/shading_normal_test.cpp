// mirror_above_surface (env/shading_normal.h): a normal whose mirror direction clears the triangle's plane
// is kept; one whose does not is turned towards the plane's normal, in the plane of the two, just far
// enough that the mirror direction meets min(0.9 v.ng, 0.01): checked against the reflection itself.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "env/shading_normal.h"

namespace envshadow {
namespace {

const glm::dvec3 kUp(0.0, 0.0, 1.0);

glm::dvec3 tilted(double degrees, const glm::dvec3& towards) {
    const double a = glm::radians(degrees);
    return std::cos(a) * kUp + std::sin(a) * towards;
}

double mirror_height(const glm::dvec3& n, const glm::dvec3& view) {
    return glm::dot(glm::reflect(-view, n), kUp);
}

TEST(MirrorAboveSurface, KeepsANormalWhoseMirrorClearsThePlane) {
    const glm::dvec3 view = tilted(30.0, {1.0, 0.0, 0.0});
    const glm::dvec3 n = tilted(20.0, {0.0, 1.0, 0.0});
    EXPECT_EQ(mirror_above_surface(n, kUp, view), n);
}

TEST(MirrorAboveSurface, LiftsJustEnoughInThePlaneOfTheTwoNormals) {
    // Viewed from 60 degrees off the normal, a normal tilted 50 degrees away from the viewer mirrors the view
    // 40 degrees below the plane.
    const glm::dvec3 view = tilted(60.0, {1.0, 0.0, 0.0});
    const glm::dvec3 n = tilted(50.0, {-1.0, 0.0, 0.0});
    ASSERT_LT(mirror_height(n, view), 0.0);
    const glm::dvec3 lifted = mirror_above_surface(n, kUp, view);
    EXPECT_NEAR(glm::length(lifted), 1.0, 1e-12);
    EXPECT_NEAR(lifted.y, 0.0, 1e-12);  // in the plane of n and ng
    EXPECT_LT(lifted.x, 0.0);           // still leaning the same way, less
    EXPECT_GT(lifted.z, n.z);
    const double threshold = std::min(0.9 * glm::dot(kUp, view), 0.01);
    EXPECT_NEAR(mirror_height(lifted, view), threshold, 1e-12);
}

TEST(MirrorAboveSurface, TheViewerOnTheSideOfTheTiltToo) {
    // Seen from 10 degrees off the normal on the tilt's side, a normal tilted 70 degrees mirrors the view 40
    // degrees below the plane.
    const glm::dvec3 view = tilted(10.0, {-1.0, 0.0, 0.0});
    const glm::dvec3 n = tilted(70.0, {-1.0, 0.0, 0.0});
    ASSERT_LT(mirror_height(n, view), 0.0);
    const glm::dvec3 lifted = mirror_above_surface(n, kUp, view);
    EXPECT_NEAR(mirror_height(lifted, view), std::min(0.9 * glm::dot(kUp, view), 0.01), 1e-12);
    EXPECT_GT(lifted.z, n.z);
    EXPECT_LT(lifted.x, 0.0);
}

TEST(MirrorAboveSurface, ANormalAlongThePlanesNormalStays) {
    const glm::dvec3 view = tilted(89.9, {1.0, 0.0, 0.0});  // grazing: the threshold is 0.9 v.ng
    EXPECT_EQ(mirror_above_surface(kUp, kUp, view), kUp);
}

}  // namespace
}  // namespace envshadow
