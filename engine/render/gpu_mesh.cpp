#include "render/gpu_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "render/shader_interface.h"

namespace envshadow::render {

namespace {

// Immutable storage (flags 0) or rewritable (GL_DYNAMIC_STORAGE_BIT); an empty array gets a 1-byte buffer
// and no data.
template <class T>
gl::Buffer make_buffer(const std::vector<T>& values, GLbitfield flags = 0) {
    const std::size_t bytes = values.size() * sizeof(T);
    return gl::Buffer::create(bytes, bytes ? values.data() : nullptr, flags);
}

// Float attribute `attribute` of `components` from `buffer` (tightly packed), on binding point `attribute`.
void attach(GLuint vao, GLuint attribute, const gl::Buffer& buffer, int components) {
    glVertexArrayVertexBuffer(vao, attribute, buffer.id(), 0, GLsizei(std::size_t(components) * sizeof(float)));
    glEnableVertexArrayAttrib(vao, attribute);
    glVertexArrayAttribFormat(vao, attribute, components, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, attribute, attribute);
}

}  // namespace

void GpuMesh::make_vertex_arrays(const Mesh& mesh, GLbitfield vertex_flags) {
    positions_ = make_buffer(mesh.positions, vertex_flags);
    normals_ = make_buffer(mesh.normals, vertex_flags);
    indices_ = make_buffer(mesh.indices);
    index_count_ = GLsizei(mesh.indices.size());
    vertex_array_ = gl::VertexArray::create();
    attach(vertex_array_.id(), shader::attrib::position, positions_, 3);
    attach(vertex_array_.id(), shader::attrib::normal, normals_, 3);
    if (!mesh.texcoords.empty()) {  // never rewritten: a pose moves the vertices, not their texture coordinates
        texcoords_ = make_buffer(mesh.texcoords);
        attach(vertex_array_.id(), shader::attrib::texcoord, texcoords_, 2);
    }
    if (!mesh.tangents.empty()) {  // rewritten with the positions (a pose turns them)
        tangents_ = make_buffer(mesh.tangents, vertex_flags);
        attach(vertex_array_.id(), shader::attrib::tangent, tangents_, 4);
    }
    glVertexArrayElementBuffer(vertex_array_.id(), indices_.id());
    caster_vertex_array_ = gl::VertexArray::create();
    attach(caster_vertex_array_.id(), shader::attrib::position, positions_, 3);
    if (texcoords_) attach(caster_vertex_array_.id(), shader::attrib::texcoord, texcoords_, 2);  // masked casters
    glVertexArrayElementBuffer(caster_vertex_array_.id(), indices_.id());
}

GpuMesh::GpuMesh(const Mesh& mesh, const std::function<void(double fraction)>& progress) {
    make_vertex_arrays(mesh, 0);
    caster_lod_ = build_caster_lod(mesh.positions, mesh.indices, progress);
    caster_indices_ = make_buffer(caster_lod_.indices);
    simplified_vertex_array_ = gl::VertexArray::create();
    attach(simplified_vertex_array_.id(), shader::attrib::position, positions_, 3);
    glVertexArrayElementBuffer(simplified_vertex_array_.id(), caster_indices_.id());

    if (mesh.positions.empty()) return;
    // Flat: one unit normal everywhere, and every position on the plane through the first with it.
    if (!mesh.normals.empty() && mesh.normals.size() == mesh.positions.size()) {
        const glm::vec3 n = mesh.normals.front();
        float extent = 0.0f;
        for (const glm::vec3& p : mesh.positions) extent = std::max(extent, glm::length(p - mesh.positions.front()));
        bool flat = std::abs(glm::length(n) - 1.0f) < 1e-5f;
        for (std::size_t i = 0; flat && i < mesh.positions.size(); ++i)
            flat = glm::length(mesh.normals[i] - n) <= 1e-6f &&
                   std::abs(glm::dot(mesh.positions[i] - mesh.positions.front(), n)) <= 1e-6f * std::max(extent, 1.0f);
        if (flat) flat_normal_ = n;
    }
    set_bounds(mesh);
}

void GpuMesh::set_bounds(const Mesh& mesh) {
    bounds_min_ = glm::vec3(std::numeric_limits<float>::infinity());
    bounds_max_ = -bounds_min_;
    for (const glm::vec3& p : mesh.positions) {
        bounds_min_ = glm::min(bounds_min_, p);
        bounds_max_ = glm::max(bounds_max_, p);
    }
    if (mesh.positions.empty()) bounds_min_ = bounds_max_ = glm::vec3(0.0f);
}

// ---- deforming meshes (glTF animation) ----------------------------------------------------------

GpuMesh::GpuMesh(const Mesh& mesh, Deforming) : deforming_(true) {
    make_vertex_arrays(mesh, GL_DYNAMIC_STORAGE_BIT);
    // The casters draw the full mesh (one level): the posed shape changes every frame. Closed as the rest
    // pose is, welded by position as build_caster_lod welds a still mesh.
    caster_lod_.levels.push_back({0, std::uint32_t(mesh.indices.size()), 0.0f, is_closed_surface(mesh)});
    set_bounds(mesh);
}

void GpuMesh::update_vertices(const Mesh& posed) {
    if (!deforming_) throw std::logic_error("GpuMesh::update_vertices on a mesh made without Deforming");
    if (!posed.positions.empty()) positions_.upload(posed.positions.data(), posed.positions.size() * sizeof(glm::vec3));
    if (!posed.normals.empty()) normals_.upload(posed.normals.data(), posed.normals.size() * sizeof(glm::vec3));
    if (!posed.tangents.empty() && tangents_)
        tangents_.upload(posed.tangents.data(), posed.tangents.size() * sizeof(glm::vec4));
    bounds_min_ = posed.bounds_min;  // posing computed them: no second pass over the vertices
    bounds_max_ = posed.bounds_max;
}

void GpuMesh::draw() const {
    glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
}

void GpuMesh::draw_caster(int level, int instances) const {
    const CasterLevel& l = caster_lod_.levels[std::size_t(level)];
    glDrawElementsInstanced(GL_TRIANGLES, GLsizei(l.index_count), GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(std::uintptr_t(l.first_index) * sizeof(std::uint32_t)),
                            instances);
}

}  // namespace envshadow::render
