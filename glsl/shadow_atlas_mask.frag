#version 450 core
// Alpha-masked casters into the shadow atlas (with shadow_atlas.vert ALPHA_MASK): what is cut out casts
// nothing, so a leaf's shadow has the leaf's shape.
#include "alpha_mask.glsl"

layout(binding = UNIT_BASE_COLOR) uniform sampler2D u_base_color;
layout(location = 0) in vec2 v_texcoord;

void main() {
    if (cut_out(mask_alpha(u_base_color, v_texcoord))) discard;
}
