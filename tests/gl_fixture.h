#pragma once
// One fixture for every GL test: a headless context of the parameter's backend (egl, osmesa) with
// KHR_debug on; a test fails if GL reported any error by its end.
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/vec4.hpp>

#include "gl/context.h"
#include "gl/debug.h"
#include "gl/objects.h"
#include "gl/shader.h"
#include "glsl/embedded.h"

namespace envshadow::gl {
// Keeps ctest's test names readable (gtest would print the enum's bytes).
inline void PrintTo(Backend backend, std::ostream* out) {
    *out << to_string(backend);
}
}  // namespace envshadow::gl

namespace envshadow::testing {

class GlTest : public ::testing::TestWithParam<gl::Backend> {
protected:
    void SetUp() override {
        context_ = gl::create_context(GetParam(), gl::ContextOptions{64, 64, /*debug=*/true});
        gl::reset_debug_errors();
    }
    void TearDown() override {
        if (!context_) return;
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
        EXPECT_EQ(gl::debug_error_count(), 0) << gl::last_debug_error();
        context_.reset();
    }
    static gl::ShaderLibrary project_shaders() {
        gl::ShaderLibrary library;
        for (const glsl::File& f : glsl::files()) library.add(f.name, f.source);
        return library;
    }
    gl::Context& context() { return *context_; }

private:
    std::unique_ptr<gl::Context> context_;
};

inline std::string backend_name(const ::testing::TestParamInfo<gl::Backend>& info) {
    return std::string(gl::to_string(info.param));
}

// Runs a GLSL probe (the GLSL-vs-C++ twin tests): `program`, a compute shader of 64-wide work groups
// with `count` at uniform location 0, reads `inputs` from the storage buffer at binding 1 and writes as
// many vec4s to binding 2, which are returned.
inline std::vector<glm::vec4> run_compute_probe(const gl::Program& program, const std::vector<glm::vec4>& inputs,
                                                GLuint count) {
    const GLsizeiptr bytes = GLsizeiptr(inputs.size() * sizeof(glm::vec4));
    gl::Buffer input_buffer = gl::Buffer::create(std::size_t(bytes), inputs.data(), 0);
    gl::Buffer output_buffer = gl::Buffer::create(std::size_t(bytes), nullptr, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, input_buffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, output_buffer.id());
    program.use();
    glUniform1ui(0, count);
    glDispatchCompute((count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> outputs(inputs.size());
    glGetNamedBufferSubData(output_buffer.id(), 0, bytes, outputs.data());
    return outputs;
}

#define ENVSHADOW_INSTANTIATE_GL_TEST(Suite)                                                            \
    INSTANTIATE_TEST_SUITE_P(Headless, Suite, ::testing::Values(gl::Backend::egl, gl::Backend::osmesa), \
                             ::envshadow::testing::backend_name)

}  // namespace envshadow::testing
