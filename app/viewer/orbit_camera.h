#pragma once
// Orbit / pan / zoom about a target, for the viewer. Angles in radians; +Y up.
#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace envshadow::app {

class OrbitCamera {
public:
    OrbitCamera() = default;
    explicit OrbitCamera(const Camera& camera) { reset(camera); }

    void reset(const Camera& camera);
    Camera camera() const;

    // Drag by (dx, dy) pixels in a viewport `height` pixels tall.
    void orbit(float dx, float dy);              // left button: turn about the target
    void pan(float dx, float dy, float height);  // right/middle button: move target and eye together
    void zoom(float wheel_steps);                // scroll: multiplies the distance

    float yaw() const { return yaw_; }
    float pitch() const { return pitch_; }
    float distance() const { return distance_; }
    const glm::vec3& target() const { return target_; }

private:
    glm::vec3 target_{0.0f};
    float yaw_ = 0.0f;    // about +Y, 0 looking along -Z
    float pitch_ = 0.3f;  // above the horizon, clamped short of the poles
    float distance_ = 4.0f;
    float fov_y_degrees_ = 45.0f;
};

}  // namespace envshadow::app
