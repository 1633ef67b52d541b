#pragma once
// A scene mesh in GPU buffers: attribute 0 position, attribute 1 normal (object space), 32-bit
// indices. Needs a current GL context.
#include <glm/vec3.hpp>

#include "gl/objects.h"
#include "scene/scene.h"

namespace envshadow::render {

class GpuMesh {
public:
    explicit GpuMesh(const Mesh& mesh);
    void draw() const;                     // glDrawElements
    void draw_instanced(int count) const;  // glDrawElementsInstanced
    void bind() const { vertex_array_.bind(); }
    const glm::vec3& bounds_min() const { return bounds_min_; }
    const glm::vec3& bounds_max() const { return bounds_max_; }
    GLsizei index_count() const { return index_count_; }

private:
    gl::Buffer positions_, normals_, indices_;
    gl::VertexArray vertex_array_;
    GLsizei index_count_ = 0;
    glm::vec3 bounds_min_{0.0f}, bounds_max_{0.0f};  // from the positions (Mesh::bounds may be unset)
};

}  // namespace envshadow::render
