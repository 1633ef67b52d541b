#pragma once
// glTF 2.0 (.gltf with external or embedded buffers, .glb) to object-space Meshes, one per material:
// every triangle primitive of the default scene, flattened with its node transforms and grouped by
// its mapped material (scene/gltf_material.h). The file is checked before use
// (JSON types, accessor and buffer bounds, index ranges, material indices and factors, component types, strides, node
// cycles, finite positions, size limits); any failure is an InputError "<file>: <reason>".
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/scene.h"

namespace envshadow {

struct GltfRig;
struct GltfPartSources;

inline constexpr std::size_t kMaxGltfTriangles = 50'000'000;

// The primitives of one material (or of several glTF materials that map to the same Material).
struct GltfPart {
    std::shared_ptr<const Mesh> mesh;  // the model's own space, as for every part
    Material material;                 // mapped from the glTF material; Material{} for primitives without one
    std::string name;                  // the (first) glTF material's name, "material <index>", or "no material"
    // Where each vertex came from, for posing (scene/gltf_animation.h); null when the model has no rig.
    std::shared_ptr<const GltfPartSources> sources;
};

struct GltfModel {
    std::vector<GltfPart> parts;                   // never empty; in the order their first primitive is met
    glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};  // of all parts
    std::size_t skipped_primitives = 0;            // points and lines (warned about)
    std::vector<std::string> ignored_extensions;   // material extensions not mapped (warned about)
    // Nodes, skins and animation clips; null when nothing is skinned, morphed or animated. Skinned and
    // morphed parts' meshes hold the rest pose (default morph weights applied).
    std::shared_ptr<const GltfRig> rig;

    std::size_t triangle_count() const;
};

GltfModel load_gltf(const std::filesystem::path& path);

}  // namespace envshadow
