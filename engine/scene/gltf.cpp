#include "scene/gltf.h"

#include <stb_image.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/image.h"
#include "core/log.h"
#include "scene/gltf_accessor.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_material.h"
#include "scene/gltf_schema.h"
#include "scene/meshes.h"

namespace envshadow {
namespace {

using nlohmann::json;

constexpr std::uintmax_t kMaxFileBytes = 2'000'000'000;  // tinygltf takes unsigned int lengths
constexpr std::size_t kMaxVertices = 3 * kMaxGltfTriangles;
constexpr int kMaxNodeDepth = 1000;  // node hierarchy levels: the traversal recurses once per level
constexpr int kMaxJsonDepth = 64;    // nesting of JSON values: tinygltf converts "extras" recursively
constexpr std::size_t kMaxTextureTexels = std::size_t(1) << 28;  // all decoded textures together (1 GiB RGBA8)

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& reason) {
    throw InputError(file.string() + ": " + reason);
}

// tinygltf's messages may span lines; ours are one line.
std::string one_line(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    std::string out;
    for (const char c : text) {
        if (c == '\n')
            out += "; ";
        else if (c != '\r')
            out += c;
    }
    return out;
}

std::vector<unsigned char> read_bytes(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) fail(path, "no such file");
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) fail(path, "cannot read the file size: " + ec.message());
    if (size > kMaxFileBytes) fail(path, "file is too large (" + std::to_string(size) + " bytes)");
    std::vector<unsigned char> bytes(size);
    std::ifstream in(path, std::ios::binary);
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size)))
        fail(path, "cannot read the file");
    return bytes;
}

std::uint32_t read_u32(const unsigned char* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;  // glb is little-endian, as is every platform we build for
}

// The JSON chunk of a .glb (header: magic, version, length; then chunks of length, type, data).
std::string glb_json_chunk(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
    if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0)
        fail(path, "not a binary glTF file (bad magic)");
    if (read_u32(&bytes[4]) != 2)
        fail(path, "binary glTF version " + std::to_string(read_u32(&bytes[4])) + " (need 2)");
    if (read_u32(&bytes[8]) > bytes.size())
        fail(path, "binary glTF is truncated (header says " + std::to_string(read_u32(&bytes[8])) + " bytes)");
    const std::uint32_t json_length = read_u32(&bytes[12]);
    if (std::memcmp(&bytes[16], "JSON", 4) != 0) fail(path, "binary glTF does not start with a JSON chunk");
    if (json_length > bytes.size() - 20) fail(path, "binary glTF JSON chunk runs past the end of the file");
    return std::string(reinterpret_cast<const char*>(&bytes[20]), json_length);
}

// nlohmann's message without its "[json.exception.parse_error.101] " prefix.
std::string json_reason(const json::exception& e) {
    const std::string what = e.what();
    const auto bracket = what.find("] ");
    return what.rfind("[json.exception", 0) == 0 && bracket != std::string::npos ? what.substr(bracket + 2) : what;
}

std::string percent_decode(const std::string& uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(uint8_t(uri[i + 1])) &&
            std::isxdigit(uint8_t(uri[i + 2]))) {
            out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// An accessor's bytes, checked against its buffer view and buffer.
struct AccessorData {
    const unsigned char* bytes = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
    int component_type = 0;
};

class Flattener {
public:
    // textures: by glTF texture index, the base-colour textures the materials use (others unset); rig and
    // accessors: the animation data (null when nothing is skinned, morphed or animated).
    Flattener(const std::filesystem::path& path, const tinygltf::Model& model, std::vector<GltfMaterial> materials,
              std::vector<std::optional<MaterialTexture>> textures, const GltfRig* rig = nullptr,
              const GltfAccessors* accessors = nullptr)
        : path_(path),
          model_(model),
          materials_(std::move(materials)),
          textures_(std::move(textures)),
          part_of_material_(materials_.size() + 1, -1),
          rig_(rig),
          accessors_(accessors) {}

    GltfModel run() {
        std::vector<int> roots;
        if (model_.defaultScene >= 0 || !model_.scenes.empty()) {
            const int scene = std::max(model_.defaultScene, 0);
            if (std::size_t(scene) >= model_.scenes.size())
                fail(path_, "scene " + std::to_string(scene) + " does not exist");
            roots = model_.scenes[std::size_t(scene)].nodes;
        } else {
            // No scene at all: show every node that is nobody's child.
            std::vector<bool> is_child(model_.nodes.size(), false);
            for (const auto& node : model_.nodes)
                for (const int child : node.children)
                    if (child >= 0 && std::size_t(child) < is_child.size()) is_child[std::size_t(child)] = true;
            for (std::size_t i = 0; i < is_child.size(); ++i)
                if (!is_child[i]) roots.push_back(int(i));
        }

        state_.assign(model_.nodes.size(), Visit::never);
        for (const int root : roots) visit(root, glm::dmat4(1.0), "scene", 1);

        if (triangles_ == 0) fail(path_, "no triangles in the default scene");
        GltfModel result;
        result.skipped_primitives = skipped_;
        for (std::size_t k = 0; k < parts_.size(); ++k) {
            // Animation (scene/gltf_animation.h): skinned and morphed parts start at the rest pose.
            if (rig_ && (part_sources_[k].skinned || part_sources_[k].morphed))
                pose_rest(*rig_, part_sources_[k], parts_[k]);
            parts_[k].compute_bounds();
            result.bounds_min = k == 0 ? parts_[k].bounds_min : glm::min(result.bounds_min, parts_[k].bounds_min);
            result.bounds_max = k == 0 ? parts_[k].bounds_max : glm::max(result.bounds_max, parts_[k].bounds_max);
            result.parts.push_back({std::make_shared<const Mesh>(std::move(parts_[k])), part_materials_[k].material,
                                    part_materials_[k].name, nullptr});
            if (rig_)
                result.parts.back().sources = std::make_shared<const GltfPartSources>(std::move(part_sources_[k]));
        }
        return result;
    }

private:
    enum class Visit { never, on_path, done };

    void visit(int node_index, const glm::dmat4& parent, const std::string& parent_name, int depth) {
        if (node_index < 0 || std::size_t(node_index) >= model_.nodes.size())
            fail(path_, parent_name + " refers to node " + std::to_string(node_index) + ", which does not exist");
        if (depth > kMaxNodeDepth)
            fail(path_, "node hierarchy deeper than " + std::to_string(kMaxNodeDepth) + " levels (at node " +
                            std::to_string(node_index) + ")");
        const auto n = std::size_t(node_index);
        if (state_[n] == Visit::on_path)
            fail(path_, "node cycle: node " + std::to_string(node_index) + " is its own ancestor");
        if (state_[n] == Visit::done)
            fail(path_,
                 "node " + std::to_string(node_index) + " has more than one parent (the node graph must be a forest)");
        state_[n] = Visit::on_path;

        const tinygltf::Node& node = model_.nodes[n];
        const glm::dmat4 world = parent * local_matrix(node);
        if (node.mesh >= 0) {
            if (std::size_t(node.mesh) >= model_.meshes.size())
                fail(path_, "node " + std::to_string(node_index) + " refers to mesh " + std::to_string(node.mesh) +
                                ", which does not exist");
            add_mesh(std::size_t(node.mesh), world, node_index);
        }
        for (const int child : node.children) visit(child, world, "node " + std::to_string(node_index), depth + 1);
        state_[n] = Visit::done;
    }

    static glm::dmat4 local_matrix(const tinygltf::Node& node) {
        if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());  // column-major, as glm
        glm::dmat4 m(1.0);
        if (node.translation.size() == 3)
            m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
        if (node.rotation.size() == 4) {
            const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // w, x, y, z
            m = m * glm::mat4_cast(glm::normalize(q));
        }
        if (node.scale.size() == 3) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
        return m;
    }

    AccessorData accessor(int index, const std::string& what) const {
        if (index < 0 || std::size_t(index) >= model_.accessors.size())
            fail(path_, what + " uses accessor " + std::to_string(index) + ", which does not exist");
        const tinygltf::Accessor& a = model_.accessors[std::size_t(index)];
        const std::string name = what + " (accessor " + std::to_string(index) + ")";
        if (a.sparse.isSparse) fail(path_, name + " is sparse, which is not supported");
        if (a.bufferView < 0 || std::size_t(a.bufferView) >= model_.bufferViews.size())
            fail(path_, name + " has no valid bufferView");
        if (a.count == 0) fail(path_, name + " has count 0");
        const int component_size = tinygltf::GetComponentSizeInBytes(std::uint32_t(a.componentType));
        const int components = tinygltf::GetNumComponentsInType(std::uint32_t(a.type));
        if (component_size <= 0) fail(path_, name + " has an unknown componentType " + std::to_string(a.componentType));
        if (components <= 0) fail(path_, name + " has an unknown type");

        const tinygltf::BufferView& view = model_.bufferViews[std::size_t(a.bufferView)];
        const std::string view_name = "bufferView " + std::to_string(a.bufferView);
        if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size())
            fail(path_, view_name + " has no valid buffer");
        const std::size_t buffer_size = model_.buffers[std::size_t(view.buffer)].data.size();
        if (view.byteOffset > buffer_size || view.byteLength > buffer_size - view.byteOffset)
            fail(path_, view_name + " (bytes " + std::to_string(view.byteOffset) + " + " +
                            std::to_string(view.byteLength) + ") runs past the end of buffer " +
                            std::to_string(view.buffer) + " (" + std::to_string(buffer_size) + " bytes)");

        const std::size_t element = std::size_t(component_size) * std::size_t(components);
        const std::size_t stride = view.byteStride != 0 ? view.byteStride : element;
        if (stride < element || stride > 252 || stride % std::size_t(component_size) != 0)
            fail(path_, view_name + " has byteStride " + std::to_string(view.byteStride) + ", invalid for " + name);
        if (a.byteOffset > view.byteLength || element > view.byteLength - a.byteOffset ||
            (a.count - 1) > (view.byteLength - a.byteOffset - element) / stride)
            fail(path_, name + " (" + std::to_string(a.count) + " elements from byte " + std::to_string(a.byteOffset) +
                            ") runs past the end of " + view_name + " (" + std::to_string(view.byteLength) + " bytes)");

        AccessorData d;
        d.bytes = model_.buffers[std::size_t(view.buffer)].data.data() + view.byteOffset + a.byteOffset;
        d.stride = stride;
        d.count = a.count;
        d.component_type = a.componentType;
        return d;
    }

    AccessorData vec3_accessor(int index, const std::string& what) const {
        const AccessorData d = accessor(index, what);
        const tinygltf::Accessor& a = model_.accessors[std::size_t(index)];
        if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
            fail(path_, what + " (accessor " + std::to_string(index) + ") must be float VEC3");
        return d;
    }

    static glm::vec3 read_vec3(const AccessorData& d, std::size_t i) {
        glm::vec3 v;
        std::memcpy(&v[0], d.bytes + i * d.stride, 12);
        return v;
    }

    // The base-colour texture reference of glTF material `material`, where it has one that resolved.
    const GltfTextureRef* texture_ref(int material) const {
        if (material < 0) return nullptr;
        const GltfMaterial& m = materials_[std::size_t(material)];
        return m.base_color && textures_[std::size_t(m.base_color->texture)] ? &*m.base_color : nullptr;
    }

    // Texture coordinates of the kept vertices `source`: float, or normalised unsigned byte or short,
    // VEC2 (glTF 2.0 §3.7.2.1), through the material's KHR_texture_transform.
    std::vector<glm::vec2> read_texcoords(int index, const std::string& what, std::size_t vertex_count,
                                          const std::vector<std::uint32_t>& source, const glm::mat3& transform) const {
        const AccessorData d = accessor(index, what);
        const tinygltf::Accessor& a = model_.accessors[std::size_t(index)];
        const bool is_float = d.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT;
        const bool is_unorm = a.normalized && (d.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                               d.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
        if (a.type != TINYGLTF_TYPE_VEC2 || !(is_float || is_unorm))
            fail(path_, what + " (accessor " + std::to_string(index) +
                            ") must be VEC2 of float or of normalized unsigned byte or short");
        if (d.count != vertex_count)
            fail(path_, what + " has " + std::to_string(d.count) + " elements for " + std::to_string(vertex_count) +
                            " positions");
        std::vector<glm::vec2> out(source.size());
        for (std::size_t v = 0; v < source.size(); ++v) {
            const unsigned char* p = d.bytes + std::size_t(source[v]) * d.stride;
            glm::vec2 uv;
            if (is_float) {
                std::memcpy(&uv[0], p, 8);
                if (!std::isfinite(uv.x) || !std::isfinite(uv.y) || std::abs(uv.x) > 1e6f || std::abs(uv.y) > 1e6f)
                    fail(path_, what + " " + std::to_string(source[v]) + " is not finite or beyond 1e6");
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

    std::vector<std::uint32_t> read_indices(int index, const std::string& what, std::size_t vertex_count) const {
        const AccessorData d = accessor(index, what);
        const tinygltf::Accessor& a = model_.accessors[std::size_t(index)];
        if (a.type != TINYGLTF_TYPE_SCALAR || a.normalized ||
            (d.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
             d.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
             d.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
            fail(path_, what + " (accessor " + std::to_string(index) + ") must be unsigned byte, short or int SCALAR");
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
                fail(path_, what + ": index " + std::to_string(v) + " at position " + std::to_string(i) +
                                " is out of range (" + std::to_string(vertex_count) + " vertices)");
            out[i] = v;
        }
        return out;
    }

    // Triangle lists from the primitive's index order (strips and fans unrolled, degenerate ones dropped).
    std::vector<std::uint32_t> triangles(int mode, const std::vector<std::uint32_t>& order,
                                         const std::string& what) const {
        std::vector<std::uint32_t> out;
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            if (order.size() % 3 != 0)
                fail(path_,
                     what + " has " + std::to_string(order.size()) + " vertices, not a multiple of 3 for triangles");
            return order;
        }
        if (order.size() < 3) fail(path_, what + " has fewer than 3 vertices");
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

    void add_mesh(std::size_t mesh_index, const glm::dmat4& world, int node_index) {
        const tinygltf::Mesh& gltf_mesh = model_.meshes[mesh_index];
        const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(world)));
        const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
        for (std::size_t p = 0; p < gltf_mesh.primitives.size(); ++p) {
            const tinygltf::Primitive& prim = gltf_mesh.primitives[p];
            const std::string what = "mesh " + std::to_string(mesh_index) + " primitive " + std::to_string(p);
            const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
            if (mode < TINYGLTF_MODE_POINTS || mode > TINYGLTF_MODE_TRIANGLE_FAN)
                fail(path_, what + " has an unknown mode " + std::to_string(mode));
            if (mode < TINYGLTF_MODE_TRIANGLES) {
                log::warn(path_.string() + ": " + what + " is points or lines (mode " + std::to_string(mode) +
                          "): skipped");
                ++skipped_;
                continue;
            }
            const auto position_it = prim.attributes.find("POSITION");
            if (position_it == prim.attributes.end()) fail(path_, what + " has no POSITION attribute");
            const AccessorData positions = vec3_accessor(position_it->second, what + " POSITION");
            if (positions.count > kMaxVertices)
                fail(path_, what + " has too many vertices (" + std::to_string(positions.count) + ")");

            // Size limits before reading: the index count bounds the triangle count.
            const std::size_t order_count = prim.indices >= 0 && std::size_t(prim.indices) < model_.accessors.size()
                                                ? model_.accessors[std::size_t(prim.indices)].count
                                                : positions.count;
            if (order_count / 3 > kMaxGltfTriangles - triangles_ || positions.count > kMaxVertices - vertices_)
                fail(path_, "more than " + std::to_string(kMaxGltfTriangles) + " triangles (limit)");

            if (prim.material >= 0 && std::size_t(prim.material) >= materials_.size())
                fail(path_, what + " refers to material " + std::to_string(prim.material) + ", which does not exist");

            std::vector<std::uint32_t> order;
            if (prim.indices >= 0) {
                order = read_indices(prim.indices, what + " indices", positions.count);
            } else {
                order.resize(positions.count);
                for (std::size_t i = 0; i < order.size(); ++i) order[i] = std::uint32_t(i);
            }
            std::vector<std::uint32_t> tris = triangles(mode, order, what);

            // Keep only the vertices the triangles use (primitives often share one large vertex array).
            Mesh part;
            std::vector<std::uint32_t> source;  // accessor element of each kept vertex
            std::vector<std::uint32_t> kept(positions.count, std::numeric_limits<std::uint32_t>::max());
            for (std::uint32_t& i : tris) {
                if (kept[i] == std::numeric_limits<std::uint32_t>::max()) {
                    kept[i] = std::uint32_t(source.size());
                    source.push_back(i);
                }
                i = kept[i];
            }
            part.positions.resize(source.size());
            for (std::size_t v = 0; v < source.size(); ++v) {
                const glm::vec3 local = read_vec3(positions, source[v]);
                const glm::dvec3 w(world * glm::dvec4(glm::dvec3(local), 1.0));
                if (!std::isfinite(local.x) || !std::isfinite(local.y) || !std::isfinite(local.z) ||
                    !std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z))
                    fail(path_, what + " POSITION " + std::to_string(source[v]) + " is not finite");
                // Beyond the limit, sums and extents downstream (bounds, fitting, cameras) overflow.
                if (std::max({std::abs(w.x), std::abs(w.y), std::abs(w.z)}) > kMaxCoordinate)
                    fail(path_, what + " POSITION " + std::to_string(source[v]) +
                                    " lies beyond 1e12 after its node transforms (coordinate limit)");
                part.positions[v] = glm::vec3(w);
            }
            if (mirrored)  // a mirroring transform turns counter-clockwise faces clockwise: turn them back
                for (std::size_t t = 0; t < tris.size(); t += 3) std::swap(tris[t + 1], tris[t + 2]);
            part.indices = std::move(tris);

            const auto normal_it = prim.attributes.find("NORMAL");
            bool normals_usable = normal_it != prim.attributes.end();
            if (normals_usable) {
                const AccessorData normals = vec3_accessor(normal_it->second, what + " NORMAL");
                if (normals.count != positions.count)
                    fail(path_, what + " has " + std::to_string(normals.count) + " normals for " +
                                    std::to_string(positions.count) + " positions");
                part.normals.resize(source.size());
                for (std::size_t v = 0; v < source.size() && normals_usable; ++v) {
                    const glm::dvec3 n = normal_matrix * glm::dvec3(read_vec3(normals, source[v]));
                    const double length = glm::length(n);
                    if (!(length > 1e-12) || !std::isfinite(length)) normals_usable = false;
                    part.normals[v] = glm::vec3(n / length);
                }
                if (!normals_usable)
                    log::warn(path_.string() + ": " + what + " has zero or non-finite normals: computing them");
            }
            if (!normals_usable) compute_vertex_normals(part);

            if (const GltfTextureRef* ref = texture_ref(prim.material)) {
                const std::string set = "TEXCOORD_" + std::to_string(ref->texcoord);
                const auto it = prim.attributes.find(set);
                if (it == prim.attributes.end())
                    fail(path_, what + ": its material's base colour texture reads " + set +
                                    ", which the primitive does not have");
                part.texcoords =
                    read_texcoords(it->second, what + " " + set, positions.count, source, ref->uv_transform);
            }

            if (part.indices.empty()) continue;  // a strip or fan of degenerate triangles only
            triangles_ += part.triangle_count();
            vertices_ += part.positions.size();
            const std::size_t part_index = part_for(prim.material);
            append(part, parts_[part_index]);
            if (rig_) {  // where the vertices came from, in mesh space, for posing (scene/gltf_animation.h)
                std::vector<glm::vec3> local_positions(source.size()), local_normals(source.size());
                const glm::dmat3 normal_to_local = glm::transpose(glm::dmat3(world));
                for (std::size_t v = 0; v < source.size(); ++v) {
                    local_positions[v] = read_vec3(positions, source[v]);
                    const glm::dvec3 n = normal_to_local * glm::dvec3(part.normals[v]);
                    const double length = glm::length(n);
                    local_normals[v] = length > 1e-30 ? glm::vec3(n / length) : part.normals[v];
                }
                append_sources(read_primitive_sources(*accessors_, model_, *rig_, node_index, int(mesh_index), int(p),
                                                      source, std::move(local_positions), std::move(local_normals)),
                               part_sources_[part_index]);
            }
        }
    }

    // The part that collects the primitives of glTF material `material` (-1: none): glTF materials
    // that map to the same Material share one.
    std::size_t part_for(int material) {
        int& part = part_of_material_[std::size_t(material + 1)];
        if (part >= 0) return std::size_t(part);
        GltfMaterial mapped =
            material >= 0 ? materials_[std::size_t(material)] : GltfMaterial{Material{}, "no material", std::nullopt};
        if (texture_ref(material))
            mapped.material.base_color_texture = textures_[std::size_t(mapped.base_color->texture)];
        const auto same = std::find_if(part_materials_.begin(), part_materials_.end(),
                                       [&](const GltfMaterial& m) { return m.material.same_as(mapped.material); });
        part = int(same - part_materials_.begin());
        if (same == part_materials_.end()) {
            part_materials_.push_back(mapped);
            parts_.emplace_back();
            part_sources_.emplace_back();
        }
        return std::size_t(part);
    }

    static void append(const Mesh& primitive, Mesh& to) {
        const auto base = std::uint32_t(to.positions.size());
        to.positions.insert(to.positions.end(), primitive.positions.begin(), primitive.positions.end());
        to.normals.insert(to.normals.end(), primitive.normals.begin(), primitive.normals.end());
        to.texcoords.insert(to.texcoords.end(), primitive.texcoords.begin(), primitive.texcoords.end());
        to.indices.reserve(to.indices.size() + primitive.indices.size());
        for (const std::uint32_t i : primitive.indices) to.indices.push_back(base + i);
    }

    const std::filesystem::path& path_;
    const tinygltf::Model& model_;
    const std::vector<GltfMaterial> materials_;
    const std::vector<std::optional<MaterialTexture>> textures_;
    std::vector<int> part_of_material_;  // by glTF material index + 1 (0: no material); -1 until met
    std::vector<GltfMaterial> part_materials_;
    std::vector<Mesh> parts_;
    const GltfRig* rig_;  // animation data: null when nothing is skinned, morphed or animated
    const GltfAccessors* accessors_;
    std::vector<GltfPartSources> part_sources_;  // per part, with a rig
    std::vector<Visit> state_;
    std::size_t triangles_ = 0, vertices_ = 0;  // over all parts
    std::size_t skipped_ = 0;
};

// tinygltf's image callback: decodes, with stb_image, the images the base-colour textures use (the
// others are left undecoded) after checking their headers against the size limits.
struct ImageDecoder {
    std::vector<bool> wanted;                                 // by image index
    std::vector<std::shared_ptr<const TextureImage>> images;  // decoded, by image index
    std::size_t texels = 0;
    std::string error;  // the first failure, in our words (tinygltf's message around it is dropped)

    static bool decode(tinygltf::Image*, const int index, std::string* err, std::string*, int, int,
                       const unsigned char* bytes, int size, void* user) {
        auto& self = *static_cast<ImageDecoder*>(user);
        if (index < 0 || std::size_t(index) >= self.wanted.size() || !self.wanted[std::size_t(index)]) return true;
        const std::string what = "image " + std::to_string(index);
        const auto failed = [&](const std::string& reason) {
            if (self.error.empty()) self.error = what + ": " + reason;
            if (err) *err += self.error;
            return false;
        };
        const bool png = size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0;
        const bool jpeg = size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
        if (!png && !jpeg) return failed("not a PNG or JPEG image");
        int w = 0, h = 0, channels = 0;
        // A PNG's size straight from its IHDR chunk: stb_image's header scan refuses large ones with
        // a reason that another format's probe then overwrites.
        if (png && size >= 24 && std::memcmp(bytes + 12, "IHDR", 4) == 0) {
            const auto be32 = [](const unsigned char* p) {
                return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
            };
            w = int(std::min<std::uint32_t>(be32(bytes + 16), 1u << 30));
            h = int(std::min<std::uint32_t>(be32(bytes + 20), 1u << 30));
        } else if (!stbi_info_from_memory(bytes, size, &w, &h, &channels)) {
            return failed(std::string("cannot read its header (") + stbi_failure_reason() + ")");
        }
        if (w <= 0 || h <= 0 || w > kMaxImageWidth || h > kMaxImageHeight)
            return failed(std::to_string(w) + "x" + std::to_string(h) + " is beyond the " +
                          std::to_string(kMaxImageWidth) + "x" + std::to_string(kMaxImageHeight) + " limit");
        if (std::size_t(w) * std::size_t(h) > kMaxTextureTexels - self.texels)
            return failed("the textures together exceed " + std::to_string(kMaxTextureTexels) + " texels (limit)");
        stbi_uc* data = stbi_load_from_memory(bytes, size, &w, &h, &channels, 4);
        if (!data) return failed(std::string("cannot decode it (") + stbi_failure_reason() + ")");
        auto image = std::make_shared<TextureImage>();
        image->width = w;
        image->height = h;
        image->rgba.assign(data, data + std::size_t(w) * std::size_t(h) * 4);
        stbi_image_free(data);
        self.texels += std::size_t(w) * std::size_t(h);
        self.images[std::size_t(index)] = std::move(image);
        return true;
    }
};

TextureWrap wrap_mode(int gl_wrap) {
    switch (gl_wrap) {
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
            return TextureWrap::clamp_to_edge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
            return TextureWrap::mirrored_repeat;
        default:
            return TextureWrap::repeat;
    }
}

// The glTF textures the materials' base colours use, by texture index: their image (decoded by the
// ImageDecoder) and sampler. A texture without a PNG/JPEG source (only an extension's) is left unset,
// with a warning: its material shows its factors.
std::vector<std::optional<MaterialTexture>> resolve_textures(const std::filesystem::path& path,
                                                             const tinygltf::Model& model,
                                                             const std::vector<GltfMaterial>& materials,
                                                             const ImageDecoder& decoder) {
    std::vector<std::optional<MaterialTexture>> out(model.textures.size());
    for (const GltfMaterial& m : materials) {
        if (!m.base_color) continue;
        const auto t = std::size_t(m.base_color->texture);
        const tinygltf::Texture& texture = model.textures[t];
        if (texture.source < 0 || !decoder.images[std::size_t(texture.source)]) continue;
        MaterialTexture mt;
        mt.image = decoder.images[std::size_t(texture.source)];
        if (texture.sampler >= 0) {
            if (std::size_t(texture.sampler) >= model.samplers.size())
                fail(path, "texture " + std::to_string(t) + " refers to sampler " + std::to_string(texture.sampler) +
                               ", which does not exist");
            const tinygltf::Sampler& sampler = model.samplers[std::size_t(texture.sampler)];
            mt.wrap_s = wrap_mode(sampler.wrapS);
            mt.wrap_t = wrap_mode(sampler.wrapT);
            mt.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
        }
        out[t] = std::move(mt);
    }
    return out;
}

// tinygltf's file access, limited to regular files: it reads every image and buffer a URI names,
// and opening a FIFO (or a device) there would block or read for ever.
bool regular_file_exists(const std::string& path, void*) {
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}

std::string path_unchanged(const std::string& path, void*) {
    return path;
}

bool read_regular_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
    try {
        *out = read_bytes(path);
        return true;
    } catch (const InputError& e) {
        if (err) *err += e.what();
        return false;
    }
}

}  // namespace

GltfModel load_gltf(const std::filesystem::path& path) {
    const std::string extension = [&] {
        std::string e = path.extension().string();
        std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        return e;
    }();
    if (extension != ".gltf" && extension != ".glb") fail(path, "not a glTF file (expected .gltf or .glb)");
    const std::vector<unsigned char> bytes = read_bytes(path);
    const bool binary = extension == ".glb";
    const std::string json_text = binary ? glb_json_chunk(path, bytes) : std::string(bytes.begin(), bytes.end());

    json document;
    try {
        document = json::parse(json_text, [&](int depth, json::parse_event_t, json&) {
            if (depth > kMaxJsonDepth)
                fail(path, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
            return true;
        });
    } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers too large
        fail(path, "invalid JSON: " + json_reason(e));
    }
    check_gltf_json(path, document);
    // Extensions that change how geometry is stored; others (materials, textures) can be ignored.
    for (const auto& name : document.value("extensionsRequired", json::array()))
        for (const char* unsupported :
             {"KHR_draco_mesh_compression", "KHR_mesh_quantization", "EXT_meshopt_compression"})
            if (name == unsupported) fail(path, "requires " + std::string(unsupported) + ", which is not supported");

    GltfMaterials materials = read_gltf_materials(path, document);

    // The images the base-colour textures use, checked to exist before tinygltf reads them.
    const json textures = document.value("textures", json::array());
    const json images = document.value("images", json::array());
    ImageDecoder decoder;
    decoder.wanted.assign(images.size(), false);
    decoder.images.resize(images.size());
    for (std::size_t i = 0; i < materials.materials.size(); ++i) {
        const std::optional<GltfTextureRef>& ref = materials.materials[i].base_color;
        if (!ref) continue;
        if (std::size_t(ref->texture) >= textures.size())
            fail(path, "materials[" + std::to_string(i) + "] uses texture " + std::to_string(ref->texture) +
                           ", which does not exist");
        const json& texture = textures[std::size_t(ref->texture)];
        const auto source = texture.find("source");
        if (source == texture.end()) {
            log::warn(path.string() + ": texture " + std::to_string(ref->texture) +
                      " has no PNG or JPEG source: materials[" + std::to_string(i) + "] shows its factors");
            continue;
        }
        if (!source->is_number_unsigned() || source->get<std::size_t>() >= images.size())
            fail(path, "texture " + std::to_string(ref->texture) + " refers to image " + source->dump() +
                           ", which does not exist");
        decoder.wanted[source->get<std::size_t>()] = true;
    }
    const std::filesystem::path base_dir = path.parent_path();
    for (std::size_t i = 0; i < document.value("buffers", json::array()).size(); ++i) {
        const json& buffer = document["buffers"][i];
        if (!buffer.contains("uri")) continue;
        const std::string uri = buffer["uri"].get<std::string>();
        if (uri.rfind("data:", 0) == 0) continue;
        const std::filesystem::path file = base_dir / percent_decode(uri);
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec))
            fail(path, "buffer " + std::to_string(i) + " file " + file.string() + " not found");
    }

    for (std::size_t i = 0; i < images.size(); ++i) {
        if (!decoder.wanted[i] || !images[i].contains("uri")) continue;
        const std::string uri = images[i]["uri"].get<std::string>();
        if (uri.rfind("data:", 0) == 0) continue;
        const std::filesystem::path file = base_dir / percent_decode(uri);
        std::error_code ec;
        if (!std::filesystem::is_regular_file(file, ec))
            fail(path, "image " + std::to_string(i) + " file " + file.string() + " not found");
    }

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(ImageDecoder::decode, &decoder);
    loader.SetFsCallbacks({regular_file_exists, path_unchanged, read_regular_file, nullptr, nullptr});
    tinygltf::Model model;
    std::string err, warn;
    const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(bytes.size()),
                                                         base_dir.string())
                           : loader.LoadASCIIFromString(&model, &err, &warn, json_text.data(),
                                                        unsigned(json_text.size()), base_dir.string());
    if (!decoder.error.empty()) fail(path, decoder.error);
    if (!ok) fail(path, one_line(err.empty() ? "tinygltf could not load it" : err));
    if (!err.empty()) fail(path, one_line(err));  // tinygltf reports some errors and still returns true
    if (!warn.empty()) log::warn(path.string() + ": " + one_line(warn));

    // Animation, skins and morph targets (scene/gltf_animation.h), read only when the file has any.
    bool animated = !model.animations.empty() || !model.skins.empty();
    for (const auto& mesh : model.meshes)
        for (const auto& prim : mesh.primitives) animated = animated || !prim.targets.empty();
    const GltfAccessors accessors(path, model);
    std::shared_ptr<const GltfRig> rig;
    if (animated) rig = std::make_shared<const GltfRig>(read_gltf_rig(accessors, model));
    std::vector<std::optional<MaterialTexture>> resolved = resolve_textures(path, model, materials.materials, decoder);
    GltfModel result =
        Flattener(path, model, std::move(materials.materials), std::move(resolved), rig.get(), &accessors).run();
    result.rig = rig;
    result.ignored_extensions = std::move(materials.ignored_extensions);
    for (const std::string& name : result.ignored_extensions)
        log::warn(path.string() + ": material extension " + name + " is not supported: ignored");
    return result;
}

std::size_t GltfModel::triangle_count() const {
    std::size_t n = 0;
    for (const GltfPart& part : parts) n += part.mesh->triangle_count();
    return n;
}

}  // namespace envshadow
