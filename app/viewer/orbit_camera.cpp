#include "viewer/orbit_camera.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace envshadow::app {
namespace {
constexpr float kMaxPitch = 1.5f;  // ~86 degrees: keeps lookAt's up vector well defined
constexpr float kRadiansPerPixel = 0.008f;
constexpr float kZoomPerStep = 0.9f;
constexpr float kMinDistance = 0.05f, kMaxDistance = 1000.0f;

// Unit vector from the target towards the eye.
glm::vec3 eye_direction(float yaw, float pitch) {
    return {std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw)};
}
}  // namespace

void OrbitCamera::reset(const Camera& camera) {
    target_ = camera.target;
    fov_y_degrees_ = camera.fov_y_degrees;
    const glm::vec3 offset = camera.position - camera.target;
    distance_ = std::clamp(glm::length(offset), kMinDistance, kMaxDistance);
    const glm::vec3 d = offset / std::max(glm::length(offset), 1e-6f);
    pitch_ = std::clamp(std::asin(std::clamp(d.y, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
    yaw_ = std::atan2(d.x, d.z);
}

Camera OrbitCamera::camera() const {
    Camera c;
    c.target = target_;
    c.position = target_ + distance_ * eye_direction(yaw_, pitch_);
    c.up = {0.0f, 1.0f, 0.0f};
    c.fov_y_degrees = fov_y_degrees_;
    return c;
}

void OrbitCamera::orbit(float dx, float dy) {
    yaw_ -= dx * kRadiansPerPixel;
    pitch_ = std::clamp(pitch_ + dy * kRadiansPerPixel, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::pan(float dx, float dy, float height) {
    // One pixel moves the target by the size of a pixel at the target's distance.
    const float world_per_pixel =
        2.0f * distance_ * std::tan(glm::radians(fov_y_degrees_) * 0.5f) / std::max(height, 1.0f);
    const glm::vec3 forward = -eye_direction(yaw_, pitch_);
    const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0.0f, 1.0f, 0.0f)));
    const glm::vec3 up = glm::cross(right, forward);
    target_ += world_per_pixel * (-dx * right + dy * up);
}

void OrbitCamera::zoom(float wheel_steps) {
    distance_ = std::clamp(distance_ * std::pow(kZoomPerStep, wheel_steps), kMinDistance, kMaxDistance);
}

}  // namespace envshadow::app
