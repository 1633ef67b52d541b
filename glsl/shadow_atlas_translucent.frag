#version 450 core
// Blended casters into the shadow atlas's translucent layer (with shadow_atlas.vert ALPHA_MASK; docs/DESIGN.md
// §5.15), drawn after the opaque casters, tested against their depths and writing none: attachment 0 is
// blended to transmittance (1 - alpha) per surface, the product over the surfaces in the texel (cleared to
// 1), attachment 1 keeps the nearest such surface's depth (GL_MIN, cleared to 1).
#include "alpha_mask.glsl"

layout(binding = UNIT_BASE_COLOR) uniform sampler2D u_base_color;
layout(location = 0) in vec2 v_texcoord;

layout(location = 0) out float o_alpha;  // glBlendFunci(0, GL_ZERO, GL_ONE_MINUS_SRC_COLOR)
layout(location = 1) out float o_depth;  // glBlendEquationi(1, GL_MIN)

void main() {
    o_alpha = clamp(mask_alpha(u_base_color, v_texcoord), 0.0, 1.0);
    o_depth = gl_FragCoord.z;
}
