// glsl/latlong.glsl's lat-long functions agree with engine/env/latlong.h, the one written convention.
#include <cmath>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "env/latlong.h"
#include "gl/objects.h"
#include "gl_fixture.h"

namespace envshadow::testing {
namespace {

using LatLongGlslTest = GlTest;

// For each input (u, v, dx, dy, dz as two vec4s) writes latlong_direction(u, v) and latlong_uv(d).
constexpr const char* kProbe = R"(#version 450 core
layout(local_size_x = 64) in;
#include "latlong.glsl"
layout(std430, binding = 1) readonly buffer Inputs { vec4 inputs[]; };
layout(std430, binding = 2) writeonly buffer Outputs { vec4 outputs[]; };
layout(location = 0) uniform uint u_count;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    vec4 uv = inputs[2 * i], d = inputs[2 * i + 1];
    outputs[2 * i] = vec4(latlong_direction(uv.xy), 0.0);
    outputs[2 * i + 1] = vec4(latlong_uv(d.xyz), 0.0, 0.0);
}
)";

TEST_P(LatLongGlslTest, DirectionAndUvMatchLatlongH) {
    std::vector<glm::vec4> inputs;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    auto add = [&](glm::vec2 uv, glm::vec3 d) {
        inputs.push_back(glm::vec4(uv, 0.0f, 0.0f));
        inputs.push_back(glm::vec4(glm::normalize(d), 0.0f));
    };
    // Texel centres of a small map (including the rows at the poles and the columns at the wrap).
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 32; ++i) {
            const glm::vec2 uv((i + 0.5f) / 32.0f, (j + 0.5f) / 16.0f);
            add(uv, glm::vec3(latlong::direction(uv.x, uv.y)));
        }
    for (int k = 0; k < 512; ++k) {
        const glm::vec3 d(unit(rng) * 2 - 1, unit(rng) * 2 - 1, unit(rng) * 2 - 1);
        add(glm::vec2(unit(rng), unit(rng)), glm::length(d) > 1e-3f ? d : glm::vec3(0, 1, 0));
    }
    // The axes and the wrap direction.
    for (const glm::vec3 d : {glm::vec3(1, 0, 0), glm::vec3(0, 0, 1), glm::vec3(-1, 0, 0), glm::vec3(0, 0, -1),
                              glm::vec3(1, 0, -1e-4f), glm::vec3(0, 1, 0), glm::vec3(0, -1, 0)})
        add(glm::vec2(0.5f), d);
    const unsigned count = unsigned(inputs.size() / 2);

    gl::ShaderLibrary library = project_shaders();
    library.add("latlong_probe.comp", kProbe);
    gl::Program program = library.build({{GL_COMPUTE_SHADER, "latlong_probe.comp"}});
    const std::vector<glm::vec4> outputs = run_compute_probe(program, inputs, count);

    for (unsigned i = 0; i < count; ++i) {
        const glm::vec2 uv(inputs[2 * i]);
        const glm::dvec3 expected_direction = latlong::direction(uv.x, uv.y);
        EXPECT_LT(glm::length(glm::dvec3(glm::vec3(outputs[2 * i])) - expected_direction), 1e-5)
            << "uv " << uv.x << " " << uv.y;
        const glm::dvec3 d(glm::vec3(inputs[2 * i + 1]));
        const glm::dvec2 expected_uv = latlong::uv(glm::normalize(d));
        const glm::vec2 got(outputs[2 * i + 1]);
        double du = std::abs(got.x - expected_uv.x);
        du = std::min(du, 1.0 - du);  // u = 0 and u = 1 are the same meridian
        EXPECT_LT(du, 1e-5) << "d " << d.x << " " << d.y << " " << d.z;
        EXPECT_LT(std::abs(got.y - expected_uv.y), 1e-5) << "d " << d.x << " " << d.y << " " << d.z;
        EXPECT_GE(got.x, 0.0f);
        EXPECT_LT(got.x, 1.0f);
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, 0);
}

ENVSHADOW_INSTANTIATE_GL_TEST(LatLongGlslTest);

}  // namespace
}  // namespace envshadow::testing
