#pragma once
// TEMPORARY stand-ins for engine/scene's built-in meshes and engine/env's decomposition of builtin
// maps, until those land on main; then the tests use make_mesh() and decompose(load_environment()).
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "env/cells.h"
#include "scene/scene.h"

namespace envshadow::testing::interim {

inline std::shared_ptr<Mesh> sphere(float radius, int segments) {
    auto mesh = std::make_shared<Mesh>();
    const int rings = segments / 2;
    for (int j = 0; j <= rings; ++j)
        for (int i = 0; i <= segments; ++i) {
            const float theta = std::numbers::pi_v<float> * float(j) / float(rings);
            const float phi = 2.0f * std::numbers::pi_v<float> * float(i) / float(segments);
            const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            mesh->positions.push_back(radius * n);
            mesh->normals.push_back(n);
        }
    for (int j = 0; j < rings; ++j)
        for (int i = 0; i < segments; ++i) {
            const std::uint32_t a = std::uint32_t(j * (segments + 1) + i), b = a + 1,
                                c = a + std::uint32_t(segments + 1), d = c + 1;
            mesh->indices.insert(mesh->indices.end(), {a, c, b, b, c, d});
        }
    mesh->bounds_min = glm::vec3(-radius);
    mesh->bounds_max = glm::vec3(radius);
    return mesh;
}

inline std::shared_ptr<Mesh> box(glm::vec3 size) {
    auto mesh = std::make_shared<Mesh>();
    const glm::vec3 h = 0.5f * size;
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {-1.0f, 1.0f}) {
            glm::vec3 n(0.0f);
            n[axis] = sign;
            const glm::vec3 u(n.y != 0.0f ? 1.0f : 0.0f, n.y != 0.0f ? 0.0f : 1.0f, 0.0f);
            const glm::vec3 v = glm::cross(n, u);
            const std::uint32_t base = std::uint32_t(mesh->positions.size());
            for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
                mesh->positions.push_back(h * (n + c.x * u + c.y * v));
                mesh->normals.push_back(n);
            }
            mesh->indices.insert(mesh->indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        }
    mesh->bounds_min = -h;
    mesh->bounds_max = h;
    return mesh;
}

inline std::shared_ptr<Mesh> plane(float size) {
    auto mesh = std::make_shared<Mesh>();
    const float h = 0.5f * size;
    mesh->positions = {{-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}};
    mesh->normals.assign(4, glm::vec3(0, 1, 0));
    mesh->indices = {0, 2, 1, 0, 3, 2};
    mesh->bounds_min = glm::vec3(-h, 0, -h);
    mesh->bounds_max = glm::vec3(h, 0, h);
    return mesh;
}

// Fibonacci directions over the sphere (or the upper hemisphere).
inline std::vector<glm::vec3> fibonacci(int n, bool upper_only) {
    std::vector<glm::vec3> d;
    const float golden = std::numbers::pi_v<float> * (3.0f - std::sqrt(5.0f));
    for (int i = 0; i < n; ++i) {
        const float y = upper_only ? 1.0f - (float(i) + 0.5f) / float(n) : 1.0f - 2.0f * (float(i) + 0.5f) / float(n);
        const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
        d.push_back({r * std::cos(golden * float(i)), y, r * std::sin(golden * float(i))});
    }
    return d;
}

// Cells of builtin:constant (radiance 1 everywhere): N equal cells.
inline std::vector<Cell> constant_cells(int n) {
    std::vector<Cell> cells;
    const float solid_angle = 4.0f * std::numbers::pi_v<float> / float(n);
    for (const glm::vec3& d : fibonacci(n, false)) {
        Cell c;
        c.direction = d;
        c.radiance = glm::vec3(solid_angle);
        c.solid_angle = solid_angle;
        c.cos_radius = c.cos_radius_weighted = 1.0f - solid_angle / (2.0f * std::numbers::pi_v<float>);
        cells.push_back(c);
    }
    return cells;
}

// A sky: a sun of total radiance `sun` in a small cell towards `sun_direction`, and n - 1 cells of a
// dim blue upper hemisphere.
inline std::vector<Cell> sky_cells(int n, glm::vec3 sun_direction, float sun) {
    std::vector<Cell> cells;
    Cell s;
    s.direction = glm::normalize(sun_direction);
    s.radiance = glm::vec3(sun);
    s.solid_angle = 1e-3f;
    s.cos_radius = s.cos_radius_weighted = 1.0f - 1e-3f / (2.0f * std::numbers::pi_v<float>);
    cells.push_back(s);
    const float solid_angle = 2.0f * std::numbers::pi_v<float> / float(n - 1);
    for (const glm::vec3& d : fibonacci(n - 1, true)) {
        Cell c;
        c.direction = d;
        c.radiance = glm::vec3(0.3f, 0.45f, 0.7f) * solid_angle;
        c.solid_angle = solid_angle;
        c.cos_radius = c.cos_radius_weighted = 1.0f - solid_angle / (2.0f * std::numbers::pi_v<float>);
        cells.push_back(c);
    }
    return cells;
}

}  // namespace envshadow::testing::interim
