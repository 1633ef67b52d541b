#version 450 core
// Evaluates glsl/ggx.glsl over a grid of inputs for tests/brdf/ggx_glsl_test.cpp.
layout(local_size_x = 64) in;

#include "ggx.glsl"

// x: cos theta_h (and t = r.l), y: n.l, z: n.v, w: alpha^2.
layout(std430, binding = 1) readonly buffer ProbeInputs { vec4 probe_inputs[]; };
// x: ggx_distribution, y: smith_visibility (z, w: 0).
layout(std430, binding = 2) writeonly buffer ProbeOutputs { vec4 probe_outputs[]; };

layout(location = 0) uniform uint u_count;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    vec4 p = probe_inputs[i];
    probe_outputs[i] = vec4(ggx_distribution(p.x, p.w), smith_visibility(p.y, p.z, p.w), 0.0, 0.0);
}
