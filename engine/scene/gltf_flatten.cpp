#include "scene/gltf_flatten.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
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

#include "core/log.h"
#include "scene/gltf_accessor.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_geometry.h"
#include "scene/meshes.h"

namespace envshadow {
namespace {

constexpr int kMaxNodeDepth = 1000;  // node hierarchy levels: the traversal keeps one entry per level on its path

class Flattener {
public:
    // textures: by glTF texture index, the base-colour and emission textures the materials use (others unset); rig and
    // accessors: the animation data (null when nothing is skinned, morphed or animated).
    Flattener(const std::filesystem::path& path, const tinygltf::Model& model, std::vector<GltfMaterial> materials,
              std::vector<std::optional<MaterialTexture>> textures, const GltfRig* rig = nullptr,
              const GltfAccessors* accessors = nullptr)
        : path_(path),
          model_(model),
          geometry_(path, model),
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
                geometry_.fail("scene " + std::to_string(scene) + " does not exist");
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
        for (const int root : roots) visit(root);

        if (triangles_ == 0) geometry_.fail("no triangles in the default scene");
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

    // Depth first from `root`, each node's meshes added on entering it, its children in order. Iterative (a
    // stack of the nodes on the path), so that a deep chain costs heap, not the call stack: the mesh work's
    // frames are large under the sanitizers.
    void visit(int root) {
        struct OnPath {
            std::size_t node;
            glm::dmat4 world;
            std::size_t next_child = 0;
        };
        std::vector<OnPath> path;
        const auto enter = [&](int node_index, const glm::dmat4& parent, const std::string& parent_name) {
            if (node_index < 0 || std::size_t(node_index) >= model_.nodes.size())
                geometry_.fail(parent_name + " refers to node " + std::to_string(node_index) +
                               ", which does not exist");
            if (int(path.size()) + 1 > kMaxNodeDepth)
                geometry_.fail("node hierarchy deeper than " + std::to_string(kMaxNodeDepth) + " levels (at node " +
                               std::to_string(node_index) + ")");
            const auto n = std::size_t(node_index);
            if (state_[n] == Visit::on_path)
                geometry_.fail("node cycle: node " + std::to_string(node_index) + " is its own ancestor");
            if (state_[n] == Visit::done)
                geometry_.fail("node " + std::to_string(node_index) +
                               " has more than one parent (the node graph must be a forest)");
            state_[n] = Visit::on_path;
            const tinygltf::Node& node = model_.nodes[n];
            const glm::dmat4 world = parent * local_matrix(node);
            if (node.mesh >= 0) {
                if (std::size_t(node.mesh) >= model_.meshes.size())
                    geometry_.fail("node " + std::to_string(node_index) + " refers to mesh " +
                                   std::to_string(node.mesh) + ", which does not exist");
                add_mesh(std::size_t(node.mesh), world, node_index);
            }
            path.push_back({n, world});
        };
        enter(root, glm::dmat4(1.0), "scene");
        while (!path.empty()) {
            OnPath& top = path.back();
            const std::vector<int>& children = model_.nodes[top.node].children;
            if (top.next_child == children.size()) {
                state_[top.node] = Visit::done;
                path.pop_back();
                continue;
            }
            const int child = children[top.next_child++];
            const glm::dmat4 world = top.world;  // `top` moves when the path grows
            enter(child, world, "node " + std::to_string(top.node));
        }
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

    const GltfTextureRef* resolved(const std::optional<GltfTextureRef>& ref) const {
        return ref && textures_[std::size_t(ref->texture)] ? &*ref : nullptr;
    }
    // The texture reference whose coordinates glTF material `material`'s meshes carry (Mesh has one set):
    // the first of GltfMaterial::texture_refs() that resolved.
    const GltfTextureRef* texture_ref(int material) const {
        if (material < 0) return nullptr;
        const GltfMaterial& m = materials_[std::size_t(material)];
        for (const std::optional<GltfTextureRef>* ref : m.texture_refs())
            if (const GltfTextureRef* r = resolved(*ref)) return r;
        return nullptr;
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
                geometry_.fail(what + " has an unknown mode " + std::to_string(mode));
            if (mode < TINYGLTF_MODE_TRIANGLES) {
                log::warn(path_.string() + ": " + what + " is points or lines (mode " + std::to_string(mode) +
                          "): skipped");
                ++skipped_;
                continue;
            }
            const auto position_it = prim.attributes.find("POSITION");
            if (position_it == prim.attributes.end()) geometry_.fail(what + " has no POSITION attribute");
            const AccessorData positions = geometry_.vec3_accessor(position_it->second, what + " POSITION");
            if (positions.count > kMaxGltfVertices)
                geometry_.fail(what + " has too many vertices (" + std::to_string(positions.count) + ")");

            // Size limits before reading: the index count bounds the triangle count.
            const std::size_t order_count = prim.indices >= 0 && std::size_t(prim.indices) < model_.accessors.size()
                                                ? model_.accessors[std::size_t(prim.indices)].count
                                                : positions.count;
            if (order_count / 3 > kMaxGltfTriangles - triangles_ || positions.count > kMaxGltfVertices - vertices_)
                geometry_.fail("more than " + std::to_string(kMaxGltfTriangles) + " triangles (limit)");

            if (prim.material >= 0 && std::size_t(prim.material) >= materials_.size())
                geometry_.fail(what + " refers to material " + std::to_string(prim.material) +
                               ", which does not exist");

            std::vector<std::uint32_t> order;
            if (prim.indices >= 0) {
                order = geometry_.read_indices(prim.indices, what + " indices", positions.count);
            } else {
                order.resize(positions.count);
                for (std::size_t i = 0; i < order.size(); ++i) order[i] = std::uint32_t(i);
            }
            std::vector<std::uint32_t> tris = geometry_.triangles(mode, order, what);

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
                const glm::vec3 local = GltfGeometryReader::read_vec3(positions, source[v]);
                const glm::dvec3 w(world * glm::dvec4(glm::dvec3(local), 1.0));
                if (!std::isfinite(local.x) || !std::isfinite(local.y) || !std::isfinite(local.z) ||
                    !std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z))
                    geometry_.fail(what + " POSITION " + std::to_string(source[v]) + " is not finite");
                // Beyond the limit, sums and extents downstream (bounds, fitting, cameras) overflow.
                if (std::max({std::abs(w.x), std::abs(w.y), std::abs(w.z)}) > kMaxCoordinate)
                    geometry_.fail(what + " POSITION " + std::to_string(source[v]) +
                                   " lies beyond 1e12 after its node transforms (coordinate limit)");
                part.positions[v] = glm::vec3(w);
            }
            if (mirrored)  // a mirroring transform turns counter-clockwise faces clockwise: turn them back
                for (std::size_t t = 0; t < tris.size(); t += 3) std::swap(tris[t + 1], tris[t + 2]);
            part.indices = std::move(tris);

            const auto normal_it = prim.attributes.find("NORMAL");
            bool normals_usable = normal_it != prim.attributes.end();
            if (normals_usable) {
                const AccessorData normals = geometry_.vec3_accessor(normal_it->second, what + " NORMAL");
                if (normals.count != positions.count)
                    geometry_.fail(what + " has " + std::to_string(normals.count) + " normals for " +
                                   std::to_string(positions.count) + " positions");
                part.normals.resize(source.size());
                for (std::size_t v = 0; v < source.size() && normals_usable; ++v) {
                    const glm::dvec3 n = normal_matrix * glm::dvec3(GltfGeometryReader::read_vec3(normals, source[v]));
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
                    geometry_.fail(what + ": its material's textures read " + set +
                                   ", which the primitive does not have");
                part.texcoords =
                    geometry_.read_texcoords(it->second, what + " " + set, positions.count, source, ref->uv_transform);
            }

            if (part.indices.empty()) continue;  // a strip or fan of degenerate triangles only
            const std::size_t part_index = part_for(prim.material);
            if (part_materials_[part_index].material.normal_texture)
                read_tangents(prim, what, positions.count, source, world, part);
            triangles_ += part.triangle_count();
            vertices_ += part.positions.size();
            append(part, parts_[part_index]);
            if (rig_) {  // where the vertices came from, in mesh space, for posing (scene/gltf_animation.h)
                std::vector<glm::vec3> local_positions(source.size()), local_normals(source.size());
                const glm::dmat3 normal_to_local = glm::transpose(glm::dmat3(world));
                for (std::size_t v = 0; v < source.size(); ++v) {
                    local_positions[v] = GltfGeometryReader::read_vec3(positions, source[v]);
                    const glm::dvec3 n = normal_to_local * glm::dvec3(part.normals[v]);
                    const double length = glm::length(n);
                    local_normals[v] = length > 1e-30 ? glm::vec3(n / length) : part.normals[v];
                }
                GltfPartSources sources =
                    read_primitive_sources(*accessors_, model_, *rig_, node_index, int(mesh_index), int(p), source,
                                           std::move(local_positions), std::move(local_normals));
                if (!part.tangents.empty()) {  // back through the node's transform, as read_tangents took them
                    const glm::dmat3 to_local = glm::inverse(glm::dmat3(world));
                    for (std::size_t v = 0; v < source.size(); ++v)
                        sources.vertices[v].tangent =
                            transform_tangent(to_local, part.tangents[v], glm::dvec3(sources.vertices[v].normal));
                }
                append_sources(sources, part_sources_[part_index]);
            }
        }
    }

    // The primitive's TANGENT (float VEC4, glTF 2.0 §3.7.2.1) through the node's transform, or, without one,
    // tangents from its normals and texture coordinates (compute_vertex_tangents). Its normal map needs them.
    void read_tangents(const tinygltf::Primitive& prim, const std::string& what, std::size_t vertex_count,
                       const std::vector<std::uint32_t>& source, const glm::dmat4& world, Mesh& part) const {
        const auto it = prim.attributes.find("TANGENT");
        if (it == prim.attributes.end()) {
            compute_vertex_tangents(part);
            return;
        }
        const AccessorData d = geometry_.accessor(it->second, what + " TANGENT");
        const tinygltf::Accessor& a = model_.accessors[std::size_t(it->second)];
        if (a.type != TINYGLTF_TYPE_VEC4 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
            geometry_.fail(what + " TANGENT (accessor " + std::to_string(it->second) + ") must be float VEC4");
        if (d.count != vertex_count)
            geometry_.fail(what + " has " + std::to_string(d.count) + " tangents for " + std::to_string(vertex_count) +
                           " positions");
        const glm::dmat3 linear(world);
        part.tangents.resize(source.size());
        bool usable = true;
        for (std::size_t v = 0; v < source.size() && usable; ++v) {
            glm::vec4 t;
            std::memcpy(&t[0], d.bytes + std::size_t(source[v]) * d.stride, 16);
            const bool signed_w = std::isfinite(t.w) && t.w != 0.0f;
            t.w = t.w < 0.0f ? -1.0f : 1.0f;
            part.tangents[v] = transform_tangent(linear, t, glm::dvec3(part.normals[v]));
            usable = signed_w && glm::vec3(part.tangents[v]) != glm::vec3(0.0f);
        }
        if (!usable) {
            log::warn(path_.string() + ": " + what + " has zero, non-finite or unsigned tangents: computing them");
            compute_vertex_tangents(part);
        }
    }

    // The part that collects the primitives of glTF material `material` (-1: none): glTF materials
    // that map to the same Material share one.
    std::size_t part_for(int material) {
        int& part = part_of_material_[std::size_t(material + 1)];
        if (part >= 0) return std::size_t(part);
        GltfMaterial mapped;
        if (material >= 0)
            mapped = materials_[std::size_t(material)];
        else
            mapped.name = "no material";
        if (const GltfTextureRef* base = resolved(mapped.base_color))
            mapped.material.base_color_texture = textures_[std::size_t(base->texture)];
        // The other textures are used only where they read the base colour's coordinates (Mesh has one set).
        const auto on_mesh_coordinates = [&](const GltfTextureRef* ref, const char* what) {
            if (!ref) return false;
            const GltfTextureRef& coords = *texture_ref(material);
            if (ref->texcoord == coords.texcoord && ref->uv_transform == coords.uv_transform) return true;
            log::warn(path_.string() + ": " + mapped.name + ": the " + what +
                      " texture reads other texture coordinates than the base colour's, which is not supported: "
                      "it is ignored");
            return false;
        };
        if (const GltfTextureRef* parameters = resolved(mapped.metallic_roughness);
            mapped.material.metallic_roughness && on_mesh_coordinates(parameters, "metallic-roughness")) {
            mapped.material.metallic_roughness_texture = textures_[std::size_t(parameters->texture)];
            mapped.material.metallic_roughness_texture->srgb = false;  // data: roughness in G, metalness in B
        }
        if (const GltfTextureRef* emission = resolved(mapped.emission); on_mesh_coordinates(emission, "emission"))
            mapped.material.emission_texture = textures_[std::size_t(emission->texture)];
        if (const GltfTextureRef* occlusion = resolved(mapped.occlusion); on_mesh_coordinates(occlusion, "occlusion")) {
            mapped.material.occlusion_texture = textures_[std::size_t(occlusion->texture)];
            mapped.material.occlusion_texture->srgb = false;  // data: the R channel as stored
        }
        if (const GltfTextureRef* normal = resolved(mapped.normal); on_mesh_coordinates(normal, "normal")) {
            mapped.material.normal_texture = textures_[std::size_t(normal->texture)];
            mapped.material.normal_texture->srgb = false;  // data: a tangent-space direction
        }
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
        to.tangents.insert(to.tangents.end(), primitive.tangents.begin(), primitive.tangents.end());
        to.indices.reserve(to.indices.size() + primitive.indices.size());
        for (const std::uint32_t i : primitive.indices) to.indices.push_back(base + i);
    }

    const std::filesystem::path& path_;
    const tinygltf::Model& model_;
    const GltfGeometryReader geometry_;
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

}  // namespace

GltfModel flatten_gltf(const std::filesystem::path& path, const tinygltf::Model& model,
                       std::vector<GltfMaterial> materials, std::vector<std::optional<MaterialTexture>> textures,
                       const GltfRig* rig, const GltfAccessors* accessors) {
    return Flattener(path, model, std::move(materials), std::move(textures), rig, accessors).run();
}

}  // namespace envshadow
