#pragma once
// How the environment map sits in the world: the one place the scene's rotation is applied
// (docs/DESIGN.md §2). Cells and lat-long texels are in map space; world = R_y(rotation) * map, a
// right-handed rotation about +Y (positive degrees turn +X towards -Z, as seen from above). The
// renderer's lights and background and the reference renderer all go through these.
#include <glm/ext/matrix_transform.hpp>
#include <glm/mat3x3.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

namespace envshadow {

inline glm::mat3 world_from_map(float rotation_degrees) {
    return glm::mat3(glm::rotate(glm::mat4(1.0f), glm::radians(rotation_degrees), glm::vec3(0.0f, 1.0f, 0.0f)));
}

// The inverse: a world direction to the map's (for looking up the map).
inline glm::mat3 map_from_world(float rotation_degrees) {
    return glm::transpose(world_from_map(rotation_degrees));
}

inline glm::vec3 world_direction_from_map(const glm::vec3& map_direction, float rotation_degrees) {
    return world_from_map(rotation_degrees) * map_direction;
}

}  // namespace envshadow
