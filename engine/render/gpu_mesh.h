#pragma once
// A scene mesh in GPU buffers: attributes shader::attrib::position and normal (object space) and, where
// the mesh has them, texcoord and tangent; 32-bit indices; and the shadow-caster levels of detail
// (render/caster_lod.h) in a second index buffer over the same positions. Needs a current GL context.
#include <functional>
#include <optional>

#include <glm/vec3.hpp>

#include "gl/objects.h"
#include "render/caster_lod.h"
#include "scene/scene.h"

namespace envshadow::render {

class GpuMesh {
public:
    // `progress`: the fraction of the work done, while the shadow-caster LOD is built (render/caster_lod.h).
    explicit GpuMesh(const Mesh& mesh, const std::function<void(double fraction)>& progress = {});
    // A deforming mesh (glTF skins and morphs, scene/gltf_animation.h): positions and normals in
    // dynamic-storage buffers that update_vertices() rewrites every frame, and no caster LOD (level 0
    // only: simplified levels would be of the bind pose, not of the frame's).
    struct Deforming {};
    GpuMesh(const Mesh& mesh, Deforming);
    // The posed positions, normals and tangents (same vertex count and indices as the mesh given to the
    // constructor); its bounds must be set (MeshDeformation's poses are).
    void update_vertices(const Mesh& posed);
    void draw() const;  // glDrawElements
    void bind() const { vertex_array_.bind(); }
    const glm::vec3& bounds_min() const { return bounds_min_; }
    const glm::vec3& bounds_max() const { return bounds_max_; }
    GLsizei index_count() const { return index_count_; }
    // The normal, when every vertex has it and lies on one plane (a ground).
    const std::optional<glm::vec3>& flat_normal() const { return flat_normal_; }

    // Caster levels (level 0: the full mesh, drawn from the mesh's own index buffer). Bind the caster
    // vertex array (positions only) of the level first.
    const CasterLod& caster_lod() const { return caster_lod_; }
    void bind_caster(int level) const { (level == 0 ? caster_vertex_array_ : simplified_vertex_array_).bind(); }
    void draw_caster(int level, int instances = 1) const;  // glDrawElementsInstanced of that level

private:
    gl::Buffer positions_, normals_, texcoords_, tangents_, indices_, caster_indices_;
    // Positions (and at level 0 the texture coordinates, for alpha-masked casters): with the mesh's index
    // buffer (level 0), and with the simplified levels' (1, 2, ...).
    gl::VertexArray vertex_array_, caster_vertex_array_, simplified_vertex_array_;
    GLsizei index_count_ = 0;
    CasterLod caster_lod_;
    glm::vec3 bounds_min_{0.0f}, bounds_max_{0.0f};  // from the positions (Mesh::bounds may be unset)
    std::optional<glm::vec3> flat_normal_;
    bool deforming_ = false;
    void set_bounds(const Mesh& mesh);
    // The buffers of positions, normals and tangents (with `vertex_flags`), texture coordinates and indices, the
    // shading vertex array, and the casters' (positions only; level 0's with the mesh's indices).
    void make_vertex_arrays(const Mesh& mesh, GLbitfield vertex_flags);
};

}  // namespace envshadow::render
