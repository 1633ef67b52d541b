#version 450 core
// Depth pre-pass (with shade.vert): only the depth buffer is written, so the N-light shading of
// shade.frag then runs once per visible pixel (engine/render/renderer.cpp). ALPHA_MASK: for masked
// surfaces, whose cut-out pixels keep the depth behind them (the shading's GL_EQUAL test then skips them).
#if defined(ALPHA_MASK)
#include "alpha_mask.glsl"

layout(binding = UNIT_BASE_COLOR) uniform sampler2D u_base_color;
layout(location = 2) in vec2 v_texcoord;
#endif

void main() {
#if defined(ALPHA_MASK)
    if (cut_out(texture(u_base_color, v_texcoord).a)) discard;
#endif
}
