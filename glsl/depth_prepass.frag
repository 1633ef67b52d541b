#version 450 core
// Depth pre-pass (with shade.vert): only the depth buffer is written, so the N-light shading of
// shade.frag then runs once per visible pixel (engine/render/renderer.cpp). ALPHA_MASK: for masked
// surfaces, whose cut-out samples keep the depth behind them (the shading's GL_EQUAL test then skips
// them): with u_alpha_to_coverage (MSAA) the sharpened alpha picks the samples, else the pixel is
// discarded whole.
#if defined(ALPHA_MASK)
#include "alpha_mask.glsl"

layout(binding = UNIT_BASE_COLOR) uniform sampler2D u_base_color;
layout(location = LOC_ALPHA_TO_COVERAGE) uniform bool u_alpha_to_coverage;
layout(location = 2) in vec2 v_texcoord;
layout(location = 0) out vec4 o_coverage;
#endif

void main() {
#if defined(ALPHA_MASK)
    float alpha = mask_alpha(u_base_color, v_texcoord);
    if (u_alpha_to_coverage)
        o_coverage = vec4(0.0, 0.0, 0.0, coverage_alpha(alpha));
    else if (cut_out(alpha))
        discard;
#endif
}
