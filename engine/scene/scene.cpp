#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "scene/gltf_animation.h"

namespace envshadow {
namespace {

// Fraction of the loop completed at time t, in [0, 1), also for negative t.
double phase(double t, double period) {
    const double x = t / period;
    const double f = x - std::floor(x);
    return f < 1.0 ? f : 0.0;
}

// Turns +Z towards the horizontal part of `direction` (no turn when it has none).
glm::mat4 facing(const glm::vec3& direction) {
    if (std::abs(direction.x) + std::abs(direction.z) <= 0.0f) return glm::mat4(1.0f);
    return glm::rotate(glm::mat4(1.0f), std::atan2(direction.x, direction.z), glm::vec3(0.0f, 1.0f, 0.0f));
}

}  // namespace

void Mesh::compute_bounds() {
    if (positions.empty()) {
        bounds_min = bounds_max = glm::vec3(0.0f);
        return;
    }
    bounds_min = glm::vec3(std::numeric_limits<float>::max());
    bounds_max = glm::vec3(std::numeric_limits<float>::lowest());
    for (const glm::vec3& p : positions) {
        bounds_min = glm::min(bounds_min, p);
        bounds_max = glm::max(bounds_max, p);
    }
}

glm::mat4 Animation::motion_at(double t) const {
    switch (kind) {
        case Kind::none:
            return glm::mat4(1.0f);
        case Kind::orbit: {
            const double angle = 2.0 * glm::pi<double>() * phase(t, period);
            const glm::vec3 offset(float(radius * std::cos(angle)), height, float(radius * std::sin(angle)));
            glm::mat4 m = glm::translate(glm::mat4(1.0f), center + offset);
            if (face_motion) m = m * facing(glm::vec3(float(-std::sin(angle)), 0.0f, float(std::cos(angle))));
            return m;
        }
        case Kind::path: {
            if (points.empty()) return glm::mat4(1.0f);
            const std::size_t n = points.size();
            double total = 0.0;
            for (std::size_t i = 0; i < n; ++i) total += glm::distance(points[i], points[(i + 1) % n]);
            if (!(total > 0.0)) return glm::translate(glm::mat4(1.0f), points[0]);
            double remaining = phase(t, period) * total;
            for (std::size_t i = 0; i < n; ++i) {
                const glm::vec3 &a = points[i], &b = points[(i + 1) % n];
                const double length = glm::distance(a, b);
                if (remaining <= length || i + 1 == n) {
                    const float s = length > 0.0 ? float(std::min(remaining / length, 1.0)) : 0.0f;
                    glm::mat4 m = glm::translate(glm::mat4(1.0f), a + s * (b - a));
                    if (face_motion) m = m * facing(b - a);
                    return m;
                }
                remaining -= length;
            }
            return glm::mat4(1.0f);  // not reached
        }
    }
    return glm::mat4(1.0f);
}

glm::mat4 Object::world_from_object(double t) const {
    const glm::mat4 m = animation.motion_at(t) * transform;
    return deformation && deformation->rigid() ? m * deformation->rigid_motion(t) : m;
}

bool Object::deforms() const {
    return deformation && !deformation->rigid();
}

std::shared_ptr<const Mesh> Object::mesh_at(double t) const {
    return deforms() ? deformation->mesh_at(t) : mesh;
}

double Object::motion_period() const {
    double period = animation.kind != Animation::Kind::none ? animation.period : 0.0;
    if (deformation) period = std::max(period, deformation->duration());
    return period;
}

glm::mat4 Camera::view_from_world() const {
    return glm::lookAtRH(position, target, up);
}

glm::mat4 Camera::clip_from_view(float aspect, float near_plane, float far_plane) const {
    return glm::perspectiveRH_NO(glm::radians(fov_y_degrees), aspect, near_plane, far_plane);
}

Camera camera_framing(const glm::vec3& lo, const glm::vec3& hi, float fov_y_degrees) {
    const glm::vec3 centre = 0.5f * (lo + hi);
    const float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    const float azimuth = glm::radians(30.0f), elevation = glm::radians(20.0f);
    const glm::vec3 towards_camera(std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
                                   std::cos(azimuth) * std::cos(elevation));
    const float distance = 1.05f * radius / std::sin(0.5f * glm::radians(fov_y_degrees));
    Camera camera;
    camera.target = centre;
    camera.position = centre + distance * towards_camera;
    camera.fov_y_degrees = fov_y_degrees;
    return camera;
}

std::size_t Scene::triangle_count() const {
    std::size_t count = 0;
    for (const Object& object : objects) count += object.mesh ? object.mesh->triangle_count() : 0;
    return count;
}

void Scene::bounds_at(double t, glm::vec3& lo, glm::vec3& hi) const {
    lo = glm::vec3(std::numeric_limits<float>::max());
    hi = glm::vec3(std::numeric_limits<float>::lowest());
    for (const Object& object : objects) {
        if (!object.mesh) continue;
        const glm::mat4 world_from_object = object.world_from_object(t);
        const std::shared_ptr<const Mesh> mesh = object.mesh_at(t);  // the pose's bounds when it deforms
        for (int corner = 0; corner < 8; ++corner) {
            const glm::vec3 p((corner & 1) ? mesh->bounds_max.x : mesh->bounds_min.x,
                              (corner & 2) ? mesh->bounds_max.y : mesh->bounds_min.y,
                              (corner & 4) ? mesh->bounds_max.z : mesh->bounds_min.z);
            const glm::vec3 w(world_from_object * glm::vec4(p, 1.0f));
            lo = glm::min(lo, w);
            hi = glm::max(hi, w);
        }
    }
    if (lo.x > hi.x) lo = hi = glm::vec3(0.0f);  // no objects
}

}  // namespace envshadow
