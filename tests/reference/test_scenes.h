#pragma once
// Hand-built scenes and maps for the reference tests: meshes made here, not by the scene loader.
#include <cmath>
#include <memory>
#include <numbers>

#include "env/environment.h"
#include "scene/scene.h"

namespace envshadow::testing {

inline EnvironmentMap uniform_map(float radiance = 1.0f, int width = 64, int height = 32) {
    EnvironmentMap map;
    map.width = width;
    map.height = height;
    map.texels.assign(std::size_t(width) * std::size_t(height), glm::vec3(radiance));
    map.source = "test:uniform";
    return map;
}

// Square of side `size` in the XZ plane at y = 0, facing +Y.
inline std::shared_ptr<const Mesh> square(float size) {
    auto mesh = std::make_shared<Mesh>();
    const float h = 0.5f * size;
    mesh->positions = {{-h, 0, -h}, {-h, 0, h}, {h, 0, h}, {h, 0, -h}};
    mesh->normals.assign(4, glm::vec3(0, 1, 0));
    mesh->indices = {0, 1, 2, 0, 2, 3};
    mesh->compute_bounds();
    return mesh;
}

// Disc of radius `radius` in the XZ plane at y = 0, facing +Y, as a fan of `segments` triangles.
inline std::shared_ptr<const Mesh> disc(float radius, int segments) {
    auto mesh = std::make_shared<Mesh>();
    mesh->positions.push_back({0, 0, 0});
    for (int k = 0; k < segments; ++k) {
        const double phi = 2.0 * std::numbers::pi * k / segments;
        mesh->positions.push_back({float(radius * std::cos(phi)), 0.0f, float(radius * std::sin(phi))});
    }
    mesh->normals.assign(mesh->positions.size(), glm::vec3(0, 1, 0));
    for (int k = 0; k < segments; ++k) {  // counter-clockwise seen from +Y
        mesh->indices.insert(mesh->indices.end(), {0u, std::uint32_t(1 + (k + 1) % segments), std::uint32_t(1 + k)});
    }
    mesh->compute_bounds();
    return mesh;
}

// UV sphere of radius `radius` about the origin with exact radial normals.
inline std::shared_ptr<const Mesh> sphere(float radius, int segments, int bands) {
    auto mesh = std::make_shared<Mesh>();
    for (int b = 0; b <= bands; ++b) {
        const double theta = std::numbers::pi * b / bands;
        for (int s = 0; s <= segments; ++s) {
            const double phi = 2.0 * std::numbers::pi * s / segments;
            const glm::vec3 n(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                              float(std::sin(theta) * std::sin(phi)));
            mesh->normals.push_back(n);
            mesh->positions.push_back(radius * n);
        }
    }
    const auto index = [&](int b, int s) { return std::uint32_t(b * (segments + 1) + s); };
    for (int b = 0; b < bands; ++b) {
        for (int s = 0; s < segments; ++s) {  // counter-clockwise seen from outside
            if (b > 0) mesh->indices.insert(mesh->indices.end(), {index(b, s), index(b, s + 1), index(b + 1, s)});
            if (b + 1 < bands) {
                mesh->indices.insert(mesh->indices.end(), {index(b, s + 1), index(b + 1, s + 1), index(b + 1, s)});
            }
        }
    }
    mesh->compute_bounds();
    return mesh;
}

inline Object object(std::shared_ptr<const Mesh> mesh, glm::mat4 transform, Material material) {
    Object o;
    o.name = "test";
    o.mesh = std::move(mesh);
    o.transform = transform;
    o.material = material;
    return o;
}

}  // namespace envshadow::testing
