// V(x, w_i): the fraction of cell i's shadow-atlas tile that sees the shaded point (docs/DESIGN.md §5.3),
// through one of three filters:
//   hard             a 2x2 percentage-closer filter against the receiver's plane (plane_pcf)
//   PCF_WIDE         3x3 such lookups one texel apart (a 4x4 texel footprint)
//   SOFT_SHADOWS     a penumbra as wide as the cell's cap (shade_soft_shadows.glsl; before PCF_WIDE)
#include "cells.glsl"
#include "shade_atlas.glsl"
#include "shade_soft_shadows.glsl"
#include "shade_surface.glsl"

layout(location = LOC_SLOPE_BIAS) uniform float u_slope_bias;  // extra bias, texels of the plane's slope

// The receiver-plane depth bias's slopes are clamped at 50 texels of depth per texel (the plane's normal
// at least 0.02 off the tile's plane in clip space): more than 5, the soft shadows' clamp, since a convex
// receiver near its terminator (a sphere under N = 1) would otherwise shadow itself.
const float kPlaneBiasMinNormalZ = 0.02;

float hard_visibility(vec2 uv, float depth, vec2 slope) {
    return plane_pcf(uv, depth, slope);
}

float wide_pcf_visibility(vec2 uv, float depth, vec2 slope) {
    float sum = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
            sum += plane_pcf(uv + vec2(x, y) * u_atlas_texel, depth + dot(slope, vec2(x, y)), slope);
    return sum / 9.0;
}

// How far, in texels, the filter's taps lie from the receiver's own point: 1 for the wide PCF's offsets
// plus the 2x2 bilinear footprint's half texel; the soft shadows clamp their taps themselves.
float filter_reach_texels() {
#if defined(PCF_WIDE) && !defined(SOFT_SHADOWS)
    return 1.5;
#else
    return 0.5;
#endif
}

// The options' filter at the receiver's clamped position uv and biased depth, each texel compared with
// the receiver's plane of depth slope `slope` per texel; `unclamped` is its position before the clamp to
// the tile (the soft shadows' disc centre).
float filtered_visibility(Light light, vec3 n, vec2 uv, vec2 unclamped, float depth, vec2 slope) {
#if defined(SOFT_SHADOWS)
    return soft_visibility(light, n, unclamped, depth, hard_visibility(uv, depth, slope), slope);
#elif defined(PCF_WIDE)
    return wide_pcf_visibility(uv, depth, slope);
#else
    return hard_visibility(uv, depth, slope);
#endif
}

// Fraction of the cell's shadow map that sees the surface. Each texel the filter reads is compared with
// the receiver's triangle's plane carried to that texel (plane_pcf, docs/DESIGN.md §5.3), so no texel of
// its own plane shadows it; the receiver's depth is lowered by the depth bias, which covers the casters'
// level of detail (at most 0.3 texel off), and by u_slope_bias texels of its plane's slope (0 by default). It may also be moved along its normal by the light's
// normal offset (more at grazing angles; 0 by default). Lookups are clamped to the tile's interior so no
// tap reads a neighbouring tile; casters keep a margin from the tile's border, so a receiver outside the
// tile reads cleared depth and is lit. Receivers beyond the far plane compare at the far plane: shadowed
// where any caster is above them.
float visibility(Light light, Surface s, float cos_theta) {
    float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    vec3 q = s.position + s.normal * (light.bias.y * max(sin_theta, 0.2));
    vec4 clip = light.clip_from_world * vec4(q, 1.0);
    vec2 margin = filter_reach_texels() * u_atlas_texel;
    vec2 unclamped = light.tile.xy + (0.5 * clip.xy + 0.5) * light.tile.zw;
    vec2 uv = clamp(unclamped, light.tile.xy + margin, light.tile.xy + light.tile.zw - margin);
    vec2 slope = receiver_depth_slope(light, s.plane_normal, kPlaneBiasMinNormalZ);
    float plane_bias = u_slope_bias * (abs(slope.x) + abs(slope.y));
    // A triangle turned away from the light while its shading normal is not (a coarse sphere's
    // terminator) is not itself in the atlas, and one within the slope clamp of grazing has a plane
    // steeper than the carried one: there the texels are compared with one depth lowered by the plane's
    // bound over the footprint, as a convex neighbour nearer the light would otherwise shadow it.
    if (dot(s.plane_normal, s.normal) * dot(s.plane_normal, light.direction.xyz) <= kPlaneBiasMinNormalZ) {
        plane_bias += (filter_reach_texels() + 0.5) * (abs(slope.x) + abs(slope.y));
        slope = vec2(0.0);
    }
    float depth = min(0.5 * clip.z + 0.5 - light.bias.x - plane_bias, 1.0);
    return filtered_visibility(light, s.normal, uv, unclamped, depth, slope);
}

// V of cell i at the surface. In ratio shading a cell whose centre is under the tangent plane counts as
// lit: its shadow lookup means nothing there, and what it keeps of its lobe (all of it for a cell too
// coarse to clip) is the part the plane does not hide (docs/DESIGN.md §4.1).
float cell_visibility(Surface s, int i) {
    float cos_theta = dot(s.normal, lights[i].direction.xyz);
#if defined(SHADING_RATIO)
    return cos_theta > 0.0 ? visibility(lights[i], s, cos_theta) : 1.0;
#else
    return visibility(lights[i], s, cos_theta);
#endif
}
