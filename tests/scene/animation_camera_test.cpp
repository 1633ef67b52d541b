#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/trigonometric.hpp>

#include "scene/meshes.h"
#include "scene/scene.h"

namespace envshadow {
namespace {

glm::vec3 position_of(const glm::mat4& m) {
    return glm::vec3(m[3]);
}
glm::vec3 forward_of(const glm::mat4& m) {
    return glm::vec3(m * glm::vec4(0, 0, 1, 0));
}  // object +Z in world

void expect_near(const glm::vec3& a, const glm::vec3& b, float tolerance = 1e-5f) {
    EXPECT_LT(glm::distance(a, b), tolerance)
        << "(" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", " << b.y << ", " << b.z << ")";
}

void expect_same_matrix(const glm::mat4& a, const glm::mat4& b, float tolerance = 1e-4f) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_NEAR(a[c][r], b[c][r], tolerance) << "column " << c << " row " << r;
}

Animation orbit() {
    Animation a;
    a.kind = Animation::Kind::orbit;
    a.period = 8.0;
    a.center = {1, 0, -2};
    a.radius = 3.0f;
    a.height = 2.5f;
    return a;
}

TEST(SceneAnimation, NoneIsIdentity) {
    expect_same_matrix(Animation{}.motion_at(3.7), glm::mat4(1.0f));
}

TEST(SceneAnimation, OrbitStartsOnPlusXAndTurnsTowardsPlusZ) {
    const Animation a = orbit();
    expect_near(position_of(a.motion_at(0.0)), {4, 2.5f, -2});
    expect_near(position_of(a.motion_at(2.0)), {1, 2.5f, 1});    // a quarter turn
    expect_near(position_of(a.motion_at(4.0)), {-2, 2.5f, -2});  // half
    // Facing along the motion: +Z at the start, -X a quarter later.
    expect_near(forward_of(a.motion_at(0.0)), {0, 0, 1});
    expect_near(forward_of(a.motion_at(2.0)), {-1, 0, 0});
}

TEST(SceneAnimation, OrbitLoopsWithItsPeriod) {
    const Animation a = orbit();
    for (const double t : {0.0, 1.3, 5.9}) {
        expect_same_matrix(a.motion_at(t), a.motion_at(t + 8.0));
        expect_same_matrix(a.motion_at(t), a.motion_at(t + 3 * 8.0));
        expect_same_matrix(a.motion_at(t), a.motion_at(t - 8.0));
        EXPECT_GT(glm::distance(position_of(a.motion_at(t)), position_of(a.motion_at(t + 4.0))), 5.9f);
    }
}

TEST(SceneAnimation, OrbitWithoutFacingOnlyTranslates) {
    Animation a = orbit();
    a.face_motion = false;
    expect_near(forward_of(a.motion_at(2.0)), {0, 0, 1});
}

TEST(SceneAnimation, PathMovesAtConstantSpeedAndLoops) {
    Animation a;
    a.kind = Animation::Kind::path;
    a.period = 12.0;
    // A 3 x 1 rectangle: 8 units around, so 1.5 s per unit.
    a.points = {{0, 1, 0}, {3, 1, 0}, {3, 1, 1}, {0, 1, 1}};
    expect_near(position_of(a.motion_at(0.0)), {0, 1, 0});
    expect_near(position_of(a.motion_at(1.5)), {1, 1, 0});
    expect_near(position_of(a.motion_at(4.5)), {3, 1, 0});
    expect_near(position_of(a.motion_at(5.25)), {3, 1, 0.5f});
    expect_near(position_of(a.motion_at(9.0)), {1, 1, 1});
    expect_near(position_of(a.motion_at(11.25)), {0, 1, 0.5f});  // the closing segment
    expect_same_matrix(a.motion_at(2.0), a.motion_at(14.0));
    // Facing along each segment.
    expect_near(forward_of(a.motion_at(1.0)), {1, 0, 0});
    expect_near(forward_of(a.motion_at(5.0)), {0, 0, 1});
    expect_near(forward_of(a.motion_at(7.0)), {-1, 0, 0});
}

TEST(SceneAnimation, ObjectMotionAppliesAfterItsTransform) {
    Object o;
    o.transform = glm::mat4(2.0f);
    o.transform[3] = glm::vec4(0, 1, 0, 1);  // scale 2, then up 1
    o.animation = orbit();
    o.animation.face_motion = false;
    const glm::vec3 p(o.world_from_object(0.0) * glm::vec4(1, 0, 0, 1));
    expect_near(p, glm::vec3(2, 1, 0) + glm::vec3(4, 2.5f, -2));
}

TEST(SceneCamera, ViewPutsTheEyeAtTheOriginLookingDownMinusZ) {
    Camera c;
    c.position = {3, 2, 5};
    c.target = {3, 2, -1};
    const glm::mat4 v = c.view_from_world();
    expect_near(glm::vec3(v * glm::vec4(c.position, 1)), {0, 0, 0});
    expect_near(glm::vec3(v * glm::vec4(c.target, 1)), {0, 0, -6});
    expect_near(glm::vec3(v * glm::vec4(3, 3, 5, 1)), {0, 1, 0});  // up stays up
    expect_near(glm::vec3(v * glm::vec4(4, 2, 5, 1)), {1, 0, 0});  // world +X is to the right
}

TEST(SceneCamera, ProjectionFollowsOpenGlClipConventions) {
    Camera c;
    c.fov_y_degrees = 60.0f;
    const glm::mat4 p = c.clip_from_view(2.0f, 0.5f, 100.0f);
    const auto ndc = [&](glm::vec3 v) {
        const glm::vec4 clip = p * glm::vec4(v, 1);
        return glm::vec3(clip) / clip.w;
    };
    EXPECT_NEAR(ndc({0, 0, -0.5f}).z, -1.0f, 1e-5f);
    EXPECT_NEAR(ndc({0, 0, -100.0f}).z, 1.0f, 1e-4f);
    // The top edge of a 60 degree field of view at distance 10 is at 10 tan 30.
    const float top = 10.0f * std::tan(glm::radians(30.0f));
    EXPECT_NEAR(ndc({0, top, -10}).y, 1.0f, 1e-5f);
    EXPECT_NEAR(ndc({2.0f * top, 0, -10}).x, 1.0f, 1e-5f);  // aspect 2
}

bool inside_frustum(const Camera& c, float aspect, const glm::vec3& lo, const glm::vec3& hi) {
    const glm::mat4 clip_from_world = c.clip_from_view(aspect, 0.01f, 1000.0f) * c.view_from_world();
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec4 p = clip_from_world * glm::vec4((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y,
                                                        (corner & 4) ? hi.z : lo.z, 1);
        if (p.w <= 0 || std::abs(p.x) > p.w || std::abs(p.y) > p.w || std::abs(p.z) > p.w) return false;
    }
    return true;
}

TEST(SceneCamera, FramingKeepsTheBoxInView) {
    for (const auto& [lo, hi] :
         {std::pair{glm::vec3(-1, 0, -1), glm::vec3(1, 2, 1)}, std::pair{glm::vec3(10, 0, 3), glm::vec3(30, 1, 4)},
          std::pair{glm::vec3(0, 0, 0), glm::vec3(0.01f, 5, 0.01f)}}) {
        const Camera c = camera_framing(lo, hi, 40.0f);
        EXPECT_GT(c.position.y, 0.5f * (lo.y + hi.y));  // from above
        for (const float aspect : {1.0f, 4.0f / 3.0f, 16.0f / 9.0f}) EXPECT_TRUE(inside_frustum(c, aspect, lo, hi));
        // and not from far away: the box's bounding sphere nearly fills the view
        EXPECT_LT(glm::distance(c.position, 0.5f * (lo + hi)),
                  1.2f * 0.5f * glm::distance(lo, hi) / std::sin(glm::radians(20.0f)));
    }
}

TEST(SceneBounds, FollowTheMovingObjects) {
    Scene s;
    Object o;
    o.mesh = std::make_shared<const Mesh>(make_mesh(BoxShape{glm::vec3(2.0f)}));
    o.animation = orbit();
    s.objects.push_back(o);
    glm::vec3 lo, hi;
    s.bounds_at(0.0, lo, hi);
    expect_near(lo, {3, 1.5f, -3});
    expect_near(hi, {5, 3.5f, -1});
    s.bounds_at(4.0, lo, hi);
    expect_near(lo, {-3, 1.5f, -3});
    expect_near(hi, {-1, 3.5f, -1});
    EXPECT_EQ(s.triangle_count(), 12u);
}

}  // namespace
}  // namespace envshadow
