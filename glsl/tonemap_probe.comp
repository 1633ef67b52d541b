#version 450 core
// Runs glsl/tonemap.glsl (built with one TONEMAP_* define) over a list of radiances for
// tests/render/tonemap_glsl_test.cpp, which compares them with the C++ twin (engine/core/tonemap.cpp).
layout(local_size_x = 64) in;

#include "tonemap.glsl"

layout(std430, binding = 1) readonly buffer ProbeInputs { vec4 probe_inputs[]; };    // rgb: radiance
layout(std430, binding = 2) writeonly buffer ProbeOutputs { vec4 probe_outputs[]; };  // rgb: sRGB-encoded

layout(location = 0) uniform uint u_count;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count) return;
    probe_outputs[i] = vec4(tonemap(probe_inputs[i].rgb, 1.0), 0.0);
}
