#version 450 core
// Evaluates glsl/brdf.glsl's cell averages over a grid of inputs for tests/brdf/brdf_glsl_test.cpp,
// which compares them with the C++ twin (engine/env/brdf.cpp).
layout(local_size_x = 64) in;

#include "brdf.glsl"

// x: cos psi_c, y: cos r, z: shininess n, w: cos theta_c.
layout(std430, binding = 1) readonly buffer ProbeInputs { vec4 probe_inputs[]; };
// x: average_specular_blended, y: average_specular_single, z: average_clamped_cosine.
layout(std430, binding = 2) writeonly buffer ProbeOutputs { vec4 probe_outputs[]; };

layout(location = 0) uniform uint u_count;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    vec4 p = probe_inputs[i];
    probe_outputs[i] = vec4(average_specular_blended(p.x, p.y, p.z), average_specular_single(p.x, p.z),
                            average_clamped_cosine(p.w, p.y), 0.0);
}
