#include "render/gpu_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "render/shader_interface.h"

namespace envshadow::render {

GpuMesh::GpuMesh(const Mesh& mesh, const std::function<void(double fraction)>& progress) {
    // Immutable storage; an empty array gets a 1-byte buffer and no data.
    auto make = [](const auto& values) {
        const std::size_t bytes = values.size() * sizeof(values[0]);
        return gl::Buffer::create(bytes, bytes ? values.data() : nullptr, 0);
    };
    positions_ = make(mesh.positions);
    normals_ = make(mesh.normals);
    indices_ = make(mesh.indices);
    index_count_ = GLsizei(mesh.indices.size());

    vertex_array_ = gl::VertexArray::create();
    const GLuint vao = vertex_array_.id();
    constexpr GLuint position = shader::attrib::position, normal = shader::attrib::normal;
    glVertexArrayVertexBuffer(vao, position, positions_.id(), 0, sizeof(glm::vec3));
    glVertexArrayVertexBuffer(vao, normal, normals_.id(), 0, sizeof(glm::vec3));
    for (GLuint attribute : {position, normal}) {
        glEnableVertexArrayAttrib(vao, attribute);
        glVertexArrayAttribFormat(vao, attribute, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, attribute, attribute);
    }
    if (!mesh.texcoords.empty()) {
        texcoords_ = make(mesh.texcoords);
        constexpr GLuint texcoord = shader::attrib::texcoord;
        glVertexArrayVertexBuffer(vao, texcoord, texcoords_.id(), 0, sizeof(glm::vec2));
        glEnableVertexArrayAttrib(vao, texcoord);
        glVertexArrayAttribFormat(vao, texcoord, 2, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, texcoord, texcoord);
    }
    glVertexArrayElementBuffer(vao, indices_.id());

    caster_lod_ = build_caster_lod(mesh.positions, mesh.indices, progress);
    caster_indices_ = make(caster_lod_.indices);
    caster_vertex_array_ = gl::VertexArray::create();
    const GLuint caster_vao = caster_vertex_array_.id();
    glVertexArrayVertexBuffer(caster_vao, position, positions_.id(), 0, sizeof(glm::vec3));
    glEnableVertexArrayAttrib(caster_vao, position);
    glVertexArrayAttribFormat(caster_vao, position, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(caster_vao, position, position);
    glVertexArrayElementBuffer(caster_vao, caster_indices_.id());

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
    auto make = [](const auto& values, GLbitfield flags) {
        const std::size_t bytes = values.size() * sizeof(values[0]);
        return gl::Buffer::create(std::max<std::size_t>(bytes, 1), bytes ? values.data() : nullptr, flags);
    };
    positions_ = make(mesh.positions, GL_DYNAMIC_STORAGE_BIT);
    normals_ = make(mesh.normals, GL_DYNAMIC_STORAGE_BIT);
    indices_ = make(mesh.indices, 0);
    index_count_ = GLsizei(mesh.indices.size());
    constexpr GLuint position = shader::attrib::position, normal = shader::attrib::normal;
    vertex_array_ = gl::VertexArray::create();
    const GLuint vao = vertex_array_.id();
    glVertexArrayVertexBuffer(vao, position, positions_.id(), 0, sizeof(glm::vec3));
    glVertexArrayVertexBuffer(vao, normal, normals_.id(), 0, sizeof(glm::vec3));
    for (GLuint attribute : {position, normal}) {
        glEnableVertexArrayAttrib(vao, attribute);
        glVertexArrayAttribFormat(vao, attribute, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, attribute, attribute);
    }
    if (!mesh.texcoords.empty()) {  // fixed: a pose moves the vertices, not their texture coordinates
        texcoords_ = make(mesh.texcoords, 0);
        constexpr GLuint texcoord = shader::attrib::texcoord;
        glVertexArrayVertexBuffer(vao, texcoord, texcoords_.id(), 0, sizeof(glm::vec2));
        glEnableVertexArrayAttrib(vao, texcoord);
        glVertexArrayAttribFormat(vao, texcoord, 2, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, texcoord, texcoord);
    }
    glVertexArrayElementBuffer(vao, indices_.id());
    // The casters draw the full mesh (one level): the posed shape changes every frame.
    caster_lod_.indices = mesh.indices;
    caster_lod_.levels.push_back({0, std::uint32_t(mesh.indices.size()), 0.0f, is_closed(mesh.indices)});
    caster_vertex_array_ = gl::VertexArray::create();
    const GLuint caster_vao = caster_vertex_array_.id();
    glVertexArrayVertexBuffer(caster_vao, position, positions_.id(), 0, sizeof(glm::vec3));
    glEnableVertexArrayAttrib(caster_vao, position);
    glVertexArrayAttribFormat(caster_vao, position, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(caster_vao, position, position);
    glVertexArrayElementBuffer(caster_vao, indices_.id());  // level 0 is the index buffer itself
    set_bounds(mesh);
}

void GpuMesh::update_vertices(const Mesh& posed) {
    if (!deforming_) throw std::logic_error("GpuMesh::update_vertices on a mesh made without Deforming");
    if (!posed.positions.empty()) positions_.upload(posed.positions.data(), posed.positions.size() * sizeof(glm::vec3));
    if (!posed.normals.empty()) normals_.upload(posed.normals.data(), posed.normals.size() * sizeof(glm::vec3));
    set_bounds(posed);
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
