// TEMPORARY, compiled only while engine/scene and engine/env have not landed on main (see
// CMakeLists.txt): the few functions of their headers that the renderer calls. Deleted once they land.
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include "env/brdf.h"
#include "scene/scene.h"

namespace envshadow {
glm::mat4 Animation::motion_at(double) const {
    return glm::mat4(1.0f);
}
glm::mat4 Camera::view_from_world() const {
    return glm::lookAt(position, target, up);
}
glm::mat4 Camera::clip_from_view(float aspect, float near_plane, float far_plane) const {
    return glm::perspective(glm::radians(fov_y_degrees), aspect, near_plane, far_plane);
}
void Scene::bounds_at(double, glm::vec3& lo, glm::vec3& hi) const {
    lo = glm::vec3(-10.0f);
    hi = glm::vec3(10.0f);
}
namespace brdf {
float diffuse_coefficient(float rho_d) {
    return rho_d / 3.14159265358979f;
}
float specular_coefficient(float rho_s, float n) {
    return rho_s * (n + 2.0f) / (2.0f * 3.14159265358979f);
}
}  // namespace brdf
}  // namespace envshadow
