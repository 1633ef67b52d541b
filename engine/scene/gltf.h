#pragma once
// glTF 2.0 (.gltf with external or embedded buffers, .glb) to one object-space Mesh: every triangle
// primitive of the default scene, flattened with its node transforms. The file is checked before use
// (JSON types, accessor and buffer bounds, index ranges, component types, strides, node cycles,
// finite positions, size limits); any failure is an InputError "<file>: <reason>".
#include <cstddef>
#include <filesystem>
#include <memory>

#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace envshadow {

inline constexpr std::size_t kMaxGltfTriangles = 50'000'000;

struct GltfModel {
    std::shared_ptr<const Mesh> mesh;
    // Triangle-weighted mean of the primitives' baseColorFactor (RGB); primitives without a material
    // count as Material{}.rho_d. Used as rho_d when the scene file gives none.
    glm::vec3 base_color{0.8f};
    std::size_t skipped_primitives = 0;  // points and lines (warned about)
};

GltfModel load_gltf(const std::filesystem::path& path);

}  // namespace envshadow
