#include "render/gpu_mesh.h"

#include <limits>

#include <glm/common.hpp>

namespace envshadow::render {

GpuMesh::GpuMesh(const Mesh& mesh) {
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
    glVertexArrayVertexBuffer(vao, 0, positions_.id(), 0, sizeof(glm::vec3));
    glVertexArrayVertexBuffer(vao, 1, normals_.id(), 0, sizeof(glm::vec3));
    for (GLuint attribute : {0u, 1u}) {
        glEnableVertexArrayAttrib(vao, attribute);
        glVertexArrayAttribFormat(vao, attribute, 3, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(vao, attribute, attribute);
    }
    glVertexArrayElementBuffer(vao, indices_.id());

    if (mesh.positions.empty()) return;
    bounds_min_ = glm::vec3(std::numeric_limits<float>::infinity());
    bounds_max_ = -bounds_min_;
    for (const glm::vec3& p : mesh.positions) {
        bounds_min_ = glm::min(bounds_min_, p);
        bounds_max_ = glm::max(bounds_max_, p);
    }
}

void GpuMesh::draw() const {
    glDrawElements(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr);
}

void GpuMesh::draw_instanced(int count) const {
    glDrawElementsInstanced(GL_TRIANGLES, index_count_, GL_UNSIGNED_INT, nullptr, count);
}

}  // namespace envshadow::render
