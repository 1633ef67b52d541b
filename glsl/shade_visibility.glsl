// V(x, w_i): the fraction of cell i's shadow-atlas tile that sees the shaded point (docs/DESIGN.md §5.3),
// through one of three filters:
//   hard             a 2x2 percentage-closer filter against the receiver's plane (plane_pcf)
//   PCF_WIDE         3x3 such lookups one texel apart (a 4x4 texel footprint)
//   SOFT_SHADOWS     a penumbra as wide as the cell's cap (shade_soft_shadows.glsl; before PCF_WIDE)
#include "cells.glsl"
#include "shade_atlas.glsl"
#include "shade_penumbra_bound.glsl"
#include "shade_soft_shadows.glsl"
#include "shade_surface.glsl"
#include "shade_tile_lookup.glsl"

float wide_pcf_visibility(TileLookup lookup) {
    float sum = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
            sum += plane_pcf(lookup.uv + vec2(x, y) * u_atlas_texel, lookup.depth + dot(lookup.slope, vec2(x, y)),
                             lookup.slope);
    return sum / 9.0;
}

// V(x, w_i) of cell i, whose centre is cos_theta above the tangent plane, through the options' filter;
// `light` = L~_i a_i, what the soft shadows' bound holds back (shade_penumbra_bound.glsl).
float visibility(Surface s, int i, float cos_theta, vec3 light) {
    TileLookup lookup = tile_lookup(lights[i], s, cos_theta);
    float hard = hard_visibility(lookup);
#if defined(SOFT_SHADOWS)
    return bounded_visibility(i, centre_sees(cos_theta, hard), soft_visibility(s, i, lookup, hard), light);
#elif defined(PCF_WIDE)
    return wide_pcf_visibility(lookup);
#else
    return hard;
#endif
}

// V of cell i at the surface. In ratio shading a cell whose centre is under the tangent plane counts as
// lit: its shadow lookup means nothing there, and what it keeps of its lobe (all of it for a cell too
// coarse to clip) is the part the plane does not hide (docs/DESIGN.md §4.1).
float cell_visibility(Surface s, int i, vec3 light) {
    float cos_theta = dot(s.normal, lights[i].direction.xyz);
#if defined(SHADING_RATIO)
    if (cos_theta <= 0.0) {
        unseen_under_the_plane(i);
        return 1.0;
    }
#endif
    return visibility(s, i, cos_theta, light);
}

// A cell the loop skips without a lookup (it reflects nothing here): under the tangent plane its centre
// does not see the point.
void skip_cell(Surface s, int i) {
    if (dot(s.normal, lights[i].direction.xyz) <= 0.0) unseen_under_the_plane(i);
}
