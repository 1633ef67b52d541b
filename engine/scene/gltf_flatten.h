#pragma once
// The flattening of a loaded glTF model (scene/gltf.h): every triangle primitive of the default scene (or,
// without scenes, of every root node), with its node transforms applied, grouped into one part per mapped
// material. Checks the node graph (indices, cycles, a forest, depth), mesh and material indices, size
// limits and finite positions as it goes; any failure is an InputError "<file>: <reason>". Internal to
// envshadow_scene: the header names tinygltf's Model.
#include <filesystem>
#include <optional>
#include <vector>

#include "scene/gltf.h"
#include "scene/gltf_material.h"

namespace tinygltf {
class Model;
}

namespace envshadow {

class GltfAccessors;

// textures: by glTF texture index, the base-colour textures the materials use (others unset); rig and
// accessors: the animation data (null when nothing is skinned, morphed or animated). The result's rig
// and ignored extensions are the caller's to fill.
GltfModel flatten_gltf(const std::filesystem::path& path, const tinygltf::Model& model,
                       std::vector<GltfMaterial> materials, std::vector<std::optional<MaterialTexture>> textures,
                       const GltfRig* rig, const GltfAccessors* accessors);

}  // namespace envshadow
