// Where a shaded point meets a cell's tile in the shadow atlas (docs/DESIGN.md §5.3).
#include "cells.glsl"
#include "shade_atlas.glsl"
#include "shade_surface.glsl"

layout(location = LOC_SLOPE_BIAS) uniform float u_slope_bias;  // extra bias, texels of the plane's slope

// The receiver-plane depth bias's slopes are clamped at 50 texels of depth per texel (the plane's normal
// at least 0.02 off the tile's plane in clip space): more than 5, the soft shadows' clamp, since a convex
// receiver near its terminator (a sphere under N = 1) would otherwise shadow itself.
const float kPlaneBiasMinNormalZ = 0.02;

// How far, in texels, the filter's taps lie from the receiver's own point: 1 for the wide PCF's offsets
// plus the 2x2 bilinear footprint's half texel; the soft shadows clamp their taps themselves.
float filter_reach_texels() {
#if defined(PCF_WIDE) && !defined(SOFT_SHADOWS)
    return 1.5;
#else
    return 0.5;
#endif
}

// The receiver in the tile: its position in the atlas clamped to the tile (uv) and before the clamp
// (unclamped: the soft shadows' disc centre), its biased depth, and its plane's depth slope per texel,
// which each texel a filter reads is compared with (plane_pcf).
struct TileLookup {
    vec2 uv;
    vec2 unclamped;
    float depth;
    vec2 slope;
};

// No texel of the receiver's own plane shadows it; its depth is lowered by the depth bias, which covers the
// casters' level of detail (at most 0.3 texel off), and by u_slope_bias texels of its plane's slope (0 by
// default). It may also be moved along its normal by the light's normal offset (more at grazing angles; 0
// by default). Lookups are clamped to the tile's interior so no tap reads a neighbouring tile; casters keep
// a margin from the tile's border, so a receiver outside the tile reads cleared depth and is lit. Receivers
// beyond the far plane compare at the far plane: shadowed where any caster is above them.
TileLookup tile_lookup(Light light, Surface s, float cos_theta) {
    float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    vec3 q = s.position + s.normal * (light.bias.y * max(sin_theta, 0.2));
    vec4 clip = light.clip_from_world * vec4(q, 1.0);
    vec2 margin = filter_reach_texels() * u_atlas_texel;
    TileLookup lookup;
    lookup.unclamped = light.tile.xy + (0.5 * clip.xy + 0.5) * light.tile.zw;
    lookup.uv = clamp(lookup.unclamped, light.tile.xy + margin, light.tile.xy + light.tile.zw - margin);
    lookup.slope = receiver_depth_slope(light, s.plane_normal, kPlaneBiasMinNormalZ);
    float plane_bias = u_slope_bias * (abs(lookup.slope.x) + abs(lookup.slope.y));
    // A triangle turned away from the light while its shading normal is not (a coarse sphere's
    // terminator) is not itself in the atlas, and one of a curved surface within the slope clamp of grazing
    // has a plane steeper than the carried one: there the texels are compared with one depth lowered by the
    // plane's bound over the footprint, as a convex neighbour nearer the light would otherwise shadow it. A
    // flat face at grazing keeps its carried plane: its texels are its own plane's, and lowered by the bound
    // (up to 50 texels of depth a texel) a wall under a roof passed the roof's top (docs/DESIGN.md §5.3).
    float grazing = s.curved ? kPlaneBiasMinNormalZ : 0.0;
    if (dot(s.plane_normal, s.normal) * dot(s.plane_normal, light.direction.xyz) <= grazing) {
        plane_bias += (filter_reach_texels() + 0.5) * (abs(lookup.slope.x) + abs(lookup.slope.y));
        lookup.slope = vec2(0.0);
    }
    lookup.depth = min(0.5 * clip.z + 0.5 - light.bias.x - plane_bias, 1.0);
    return lookup;
}

float hard_visibility(TileLookup lookup) {
    return plane_pcf(lookup.uv, lookup.depth, lookup.slope);
}
