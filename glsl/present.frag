#version 450 core
// The linear HDR frame, tone-mapped for the window (or an 8-bit target).
#include "tonemap.glsl"

layout(location = 0) in vec2 v_uv;
layout(location = LOC_EXPOSURE_SCALE) uniform float u_exposure_scale;
layout(binding = UNIT_LINEAR) uniform sampler2D u_linear;
layout(location = 0) out vec4 o_color;

void main() {
    vec4 linear = texture(u_linear, v_uv);
    o_color = vec4(tonemap(linear.rgb, u_exposure_scale), 1.0);
}
