#pragma once
// Checked reads of a glTF primitive's geometry for the flattening (scene/gltf_flatten.h): accessors checked
// against their buffer view and buffer (component types, counts, strides, bounds), positions and normals as
// float VEC3, texture coordinates, indices in range, and the primitive's triangles. Any failure is an
// InputError "<file>: <reason>". Internal to envshadow_scene: the header names tinygltf's Model.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/gltf.h"

namespace tinygltf {
class Model;
}

namespace envshadow {

inline constexpr std::size_t kMaxGltfVertices = 3 * kMaxGltfTriangles;

// An accessor's bytes, checked against its buffer view and buffer.
struct AccessorData {
    const unsigned char* bytes = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
    int component_type = 0;
};

class GltfGeometryReader {
public:
    GltfGeometryReader(const std::filesystem::path& path, const tinygltf::Model& model) : path_(path), model_(model) {}

    // Accessor `index`, checked against its buffer view and buffer; `what` names its user in errors.
    AccessorData accessor(int index, const std::string& what) const;
    // The same, which must also be float VEC3 (POSITION, NORMAL).
    AccessorData vec3_accessor(int index, const std::string& what) const;
    static glm::vec3 read_vec3(const AccessorData& d, std::size_t i);
    // Texture coordinates of the kept vertices `source`: float, or normalised unsigned byte or short,
    // VEC2 (glTF 2.0 §3.7.2.1), through the material's KHR_texture_transform.
    std::vector<glm::vec2> read_texcoords(int index, const std::string& what, std::size_t vertex_count,
                                          const std::vector<std::uint32_t>& source, const glm::mat3& transform) const;
    // Unsigned byte, short or int SCALAR indices, each below `vertex_count`.
    std::vector<std::uint32_t> read_indices(int index, const std::string& what, std::size_t vertex_count) const;
    // Triangle lists from the primitive's index order (strips and fans unrolled, degenerate ones dropped).
    std::vector<std::uint32_t> triangles(int mode, const std::vector<std::uint32_t>& order,
                                         const std::string& what) const;

    // Throws InputError "<file>: <reason>".
    [[noreturn]] void fail(const std::string& reason) const;

private:
    const std::filesystem::path& path_;
    const tinygltf::Model& model_;
};

}  // namespace envshadow
