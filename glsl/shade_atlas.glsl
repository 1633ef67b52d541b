// The shadow atlas as the shading reads it (docs/DESIGN.md §5.2, §5.3): one tile per cell, whose depths
// the light record's clip_from_world maps the world into.
#include "cells.glsl"

layout(binding = UNIT_ATLAS_DEPTH) uniform sampler2D u_atlas_depth;  // the atlas's depths (NEAREST)
layout(location = LOC_ATLAS_TEXEL) uniform vec2 u_atlas_texel;       // size of one atlas texel in uv
#if defined(TRANSLUCENT_SHADOWS)
// The blended casters (shadow_atlas_translucent.frag): the product of their 1 - alpha in each texel, and the
// depth of the nearest of them (both 1 where there is none).
layout(binding = UNIT_ATLAS_TRANSMITTANCE) uniform sampler2D u_atlas_transmittance;
layout(binding = UNIT_ATLAS_TRANSLUCENT_DEPTH) uniform sampler2D u_atlas_translucent_depth;
#endif

// Depth change per tile texel (x, y) along the receiver's tangent plane with normal n: what a lookup
// that far from the receiver's own point must allow for (docs/DESIGN.md §5.3), and what the soft
// shadows' taps compare against (no acne on planes). The normal in clip space
// is M^-T n = (M n)_k / |row_k|^2 for the orthographic M = diag(1 / half) R; slopes clamped at
// 1 / min_nz (n_clip.z at least min_nz in magnitude).
vec2 receiver_depth_slope(Light light, vec3 n, float min_nz) {
    mat3 m = mat3(light.clip_from_world);
    vec3 row_sq = vec3(dot(vec3(m[0][0], m[1][0], m[2][0]), vec3(m[0][0], m[1][0], m[2][0])),
                       dot(vec3(m[0][1], m[1][1], m[2][1]), vec3(m[0][1], m[1][1], m[2][1])),
                       dot(vec3(m[0][2], m[1][2], m[2][2]), vec3(m[0][2], m[1][2], m[2][2])));
    vec3 n_clip = normalize((m * n) / row_sq);
    float nz = n_clip.z < 0.0 ? min(n_clip.z, -min_nz) : max(n_clip.z, min_nz);
    float tile_texels = light.tile.z / u_atlas_texel.x;
    return -n_clip.xy / nz / tile_texels;  // d(0.5 z + 0.5) per texel: clip x spans 2 over tile_texels
}

// The hardware's 2x2 percentage-closer filter (bilinear weights of the four texels around uv), but each
// texel compared with the receiver's plane carried to that texel's centre, depth + slope . (centre - uv),
// rather than with one depth for all four: no texel of the receiver's own plane shadows it, with no bias
// growing with the slope, so a blocker a few texels away across a concave corner (a wall meeting a roof)
// still shadows (docs/DESIGN.md §5.3). TRANSLUCENT_SHADOWS: a texel's light is also scaled by the blended
// casters' transmittance where the receiver lies behind the nearest of them (docs/DESIGN.md §5.15).
float plane_pcf(vec2 uv, float depth, vec2 slope) {
    vec2 texel = uv / u_atlas_texel - 0.5;  // texel centres at integers
    vec2 corner = floor(texel);
    vec2 f = texel - corner;
    // textureGather at the shared corner of the four: (0, 1), (1, 1), (1, 0), (0, 0).
    vec2 shared_corner = (corner + 1.0) * u_atlas_texel;
    vec4 stored = textureGather(u_atlas_depth, shared_corner);
    vec4 dx = vec4(-f.x, 1.0 - f.x, 1.0 - f.x, -f.x), dy = vec4(1.0 - f.y, 1.0 - f.y, -f.y, -f.y);
    vec4 receiver = min(depth + slope.x * dx + slope.y * dy, 1.0);
    vec4 lit = vec4(lessThanEqual(receiver, stored));
#if defined(TRANSLUCENT_SHADOWS)
    vec4 behind = vec4(greaterThan(receiver, textureGather(u_atlas_translucent_depth, shared_corner)));
    lit *= 1.0 - behind * (1.0 - textureGather(u_atlas_transmittance, shared_corner));
#endif
    return mix(mix(lit.w, lit.z, f.x), mix(lit.x, lit.y, f.x), f.y);
}
