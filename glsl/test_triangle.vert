#version 450 core
// A coloured triangle at a given depth: used by the GL layer's tests and `envshadow render --test`.
#include "test_common.glsl"

layout(location = 0) out vec3 v_color;

void main() {
    const vec2 corners[3] = vec2[](vec2(-0.8, -0.8), vec2(0.8, -0.8), vec2(0.0, 0.8));
    gl_Position = vec4(corners[gl_VertexID] * u_scale, u_depth, 1.0);
    v_color = test_color(gl_VertexID);
}
