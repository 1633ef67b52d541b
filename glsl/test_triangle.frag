#version 450 core
#include "test_common.glsl"

layout(location = 0) in vec3 v_color;
layout(location = 0) out vec4 o_color;

void main() { o_color = vec4(u_tint * v_color, 1.0); }
