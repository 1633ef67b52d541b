#include "scene/gltf_geometry.h"

#include <tiny_gltf.h>

#include <cmath>
#include <cstring>

#include <glm/mat3x3.hpp>

#include "core/error.h"

namespace envshadow {

void GltfGeometryReader::fail(const std::string& reason) const {
    throw InputError(path_.string() + ": " + reason);
}

AccessorData GltfGeometryReader::accessor(int index, const std::string& what) const {
    if (index < 0 || std::size_t(index) >= model_.accessors.size())
        fail(what + " uses accessor " + std::to_string(index) + ", which does not exist");
    const tinygltf::Accessor& a = model_.accessors[std::size_t(index)];
    const std::string name = what + " (accessor " + std::to_string(index) + ")";
    if (a.sparse.isSparse) fail(name + " is sparse, which is not supported");
    if (a.bufferView < 0 || std::size_t(a.bufferView) >= model_.bufferViews.size())
        fail(name + " has no valid bufferView");
    if (a.count == 0) fail(name + " has count 0");
    const int component_size = tinygltf::GetComponentSizeInBytes(std::uint32_t(a.componentType));
    const int components = tinygltf::GetNumComponentsInType(std::uint32_t(a.type));
    if (component_size <= 0) fail(name + " has an unknown componentType " + std::to_string(a.componentType));
    if (components <= 0) fail(name + " has an unknown type");

    const tinygltf::BufferView& view = model_.bufferViews[std::size_t(a.bufferView)];
    const std::string view_name = "bufferView " + std::to_string(a.bufferView);
    if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size()) fail(view_name + " has no valid buffer");
    const std::size_t buffer_size = model_.buffers[std::size_t(view.buffer)].data.size();
    if (view.byteOffset > buffer_size || view.byteLength > buffer_size - view.byteOffset)
        fail(view_name + " (bytes " + std::to_string(view.byteOffset) + " + " + std::to_string(view.byteLength) +
             ") runs past the end of buffer " + std::to_string(view.buffer) + " (" + std::to_string(buffer_size) +
             " bytes)");

    const std::size_t element = std::size_t(component_size) * std::size_t(components);
    const std::size_t stride = view.byteStride != 0 ? view.byteStride : element;
    if (stride < element || stride > 252 || stride % std::size_t(component_size) != 0)
        fail(view_name + " has byteStride " + std::to_string(view.byteStride) + ", invalid for " + name);
    if (a.byteOffset > view.byteLength || element > view.byteLength - a.byteOffset ||
        (a.count - 1) > (view.byteLength - a.byteOffset - element) / stride)
        fail(name + " (" + std::to_string(a.count) + " elements from byte " + std::to_string(a.byteOffset) +
             ") runs past the end of " + view_name + " (" + std::to_string(view.byteLength) + " bytes)");

    AccessorData d;
    d.bytes = model_.buffers[std::size_t(view.buffer)].data.data() + view.byteOffset + a.byteOffset;
    d.stride = stride;
    d.count = a.count;
    d.component_type = a.componentType;
    return d;
}

AccessorData GltfGeometryReader::vec3_accessor(int index, const std::string& what) const {
    const AccessorData d = accessor(index, what);
    const tinygltf::Accessor& a = model_.accessors[std::size_t(index)];
    if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
        fail(what + " (accessor " + std::to_string(index) + ") must be float VEC3");
    return d;
}

glm::vec3 GltfGeometryReader::read_vec3(const AccessorData& d, std::size_t i) {
    glm::vec3 v;
    std::memcpy(&v[0], d.bytes + i * d.stride, 12);
    return v;
}

// Texture coordinates of the kept vertices `source`: float, or normalised unsigned byte or short,
// VEC2 (glTF 2.0 §3.7.2.1), through the material's KHR_texture_transform.
std::vector<glm::vec2> GltfGeometryReader::read_texcoords(int index, const std::string& what, std::size_t vertex_count,
                                                          const std::vector<std::uint32_t>& source,
                                                          const glm::mat3& transform) const {
    const AccessorData d = accessor(index, what);
    const tinygltf::Accessor& a = model_.accessors[std::size_t(index)];
    const bool is_float = d.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT;
    const bool is_unorm = a.normalized && (d.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                           d.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    if (a.type != TINYGLTF_TYPE_VEC2 || !(is_float || is_unorm))
        fail(what + " (accessor " + std::to_string(index) +
             ") must be VEC2 of float or of normalized unsigned byte or short");
    if (d.count != vertex_count)
        fail(what + " has " + std::to_string(d.count) + " elements for " + std::to_string(vertex_count) + " positions");
    std::vector<glm::vec2> out(source.size());
    for (std::size_t v = 0; v < source.size(); ++v) {
        const unsigned char* p = d.bytes + std::size_t(source[v]) * d.stride;
        glm::vec2 uv;
        if (is_float) {
            std::memcpy(&uv[0], p, 8);
            if (!std::isfinite(uv.x) || !std::isfinite(uv.y) || std::abs(uv.x) > 1e6f || std::abs(uv.y) > 1e6f)
                fail(what + " " + std::to_string(source[v]) + " is not finite or beyond 1e6");
        } else if (d.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
            uv = glm::vec2(p[0], p[1]) / 255.0f;
        } else {
            std::uint16_t c[2];
            std::memcpy(c, p, 4);
            uv = glm::vec2(c[0], c[1]) / 65535.0f;
        }
        out[v] = glm::vec2(transform * glm::vec3(uv, 1.0f));
    }
    return out;
}

std::vector<std::uint32_t> GltfGeometryReader::read_indices(int index, const std::string& what,
                                                            std::size_t vertex_count) const {
    const AccessorData d = accessor(index, what);
    const tinygltf::Accessor& a = model_.accessors[std::size_t(index)];
    if (a.type != TINYGLTF_TYPE_SCALAR || a.normalized ||
        (d.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
         d.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
         d.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        fail(what + " (accessor " + std::to_string(index) + ") must be unsigned byte, short or int SCALAR");
    std::vector<std::uint32_t> out(d.count);
    for (std::size_t i = 0; i < d.count; ++i) {
        const unsigned char* p = d.bytes + i * d.stride;
        std::uint32_t v = 0;
        if (d.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
            v = p[0];
        } else if (d.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
            std::uint16_t s;
            std::memcpy(&s, p, 2);
            v = s;
        } else {
            std::memcpy(&v, p, 4);
        }
        if (v >= vertex_count)
            fail(what + ": index " + std::to_string(v) + " at position " + std::to_string(i) + " is out of range (" +
                 std::to_string(vertex_count) + " vertices)");
        out[i] = v;
    }
    return out;
}

// Triangle lists from the primitive's index order (strips and fans unrolled, degenerate ones dropped).
std::vector<std::uint32_t> GltfGeometryReader::triangles(int mode, const std::vector<std::uint32_t>& order,
                                                         const std::string& what) const {
    std::vector<std::uint32_t> out;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (order.size() % 3 != 0)
            fail(what + " has " + std::to_string(order.size()) + " vertices, not a multiple of 3 for triangles");
        return order;
    }
    if (order.size() < 3) fail(what + " has fewer than 3 vertices");
    for (std::size_t i = 0; i + 2 < order.size(); ++i) {
        std::uint32_t a, b, c;
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {  // every other triangle flips to keep the winding
            a = order[i];
            b = order[i + 1 + i % 2];
            c = order[i + 2 - i % 2];
        } else {  // fan
            a = order[i + 1];
            b = order[i + 2];
            c = order[0];
        }
        if (a == b || b == c || a == c) continue;
        out.insert(out.end(), {a, b, c});
    }
    return out;
}

}  // namespace envshadow
