// SUN_PER_PIXEL (with the fraction per 2x2 pixels, docs/DESIGN.md §5.14): the sun's shadow at each pixel,
// the sun being the brightest cell where it stands out from the rest (render/lights.h, sun_light). It takes
// a large share of the light at once, so the edge of its shadow is a jump in the fraction, which the half
// rate's texels place to within two pixels. The fraction pass writes per texel the sun's share of the
// fraction, L~_s a_s / sum_i L~_i a^_i, and its V looked up alone; the shading replaces the texels' mean of
// share x V by their mean share times the fragment's own V, so the edge lies where the fragment's lookup
// puts it, and a shadow narrower than the texels is not lost between them.
#include "cells.glsl"
#include "shade_ratio.glsl"
#include "shade_reflectivity.glsl"
#include "shade_surface.glsl"
#include "shade_visibility.glsl"

layout(location = LOC_SUN_CELL) uniform int u_sun_cell;  // the sun's cell; -1: none

// Whether the shading looks the sun up again at this fragment: there is a sun and its centre is above the
// fragment's tangent plane. Under it the ratio's convention counts the cell lit (cell_visibility), which
// the texels' mean tempers across the terminator and a lookup of the fragment's own would not. Everywhere
// else it is looked up, also where the texels agree: a shadow narrower than two pixels falls between them.
bool sun_looked_up(Surface s) {
    return u_sun_cell >= 0 && dot(s.normal, lights[u_sun_cell].direction.xyz) > 0.0;
}

// V of the sun's cell alone, the same in both passes: 1 where its centre is under the tangent plane (the
// ratio's convention, cell_visibility); soft shadows without the bound across cells, whose light through
// empty taps counts only where the cell's own centre sees the point.
float sun_visibility(Surface s) {
    int i = u_sun_cell;
    float cos_theta = dot(s.normal, lights[i].direction.xyz);
    if (cos_theta <= 0.0) return 1.0;
    TileLookup lookup = tile_lookup(lights[i], s, cos_theta);
    float hard = hard_visibility(lookup);
#if defined(SOFT_SHADOWS)
    vec2 v = soft_visibility(s, i, lookup, hard);
    return centre_sees(cos_theta, hard) ? v.x : v.x - v.y;
#elif defined(PCF_WIDE)
    return wide_pcf_visibility(lookup);
#else
    return hard;
#endif
}

#if defined(SHADOWED_FRACTION_OUT)
layout(location = 2) out vec4 o_sun;

// The fraction pass's third target: the sun's share of the fraction (RGB, shadowed_fraction's rule: 0 where
// no cell reflects) and its visibility (A); share 0 where there is no sun.
void write_sun_texel(Surface s, vec3 whole_lobe) {
    if (u_sun_cell < 0) {
        o_sun = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    vec3 light = lights[u_sun_cell].radiance.rgb * reflectivity(s, u_sun_cell).kept;
    o_sun = vec4(shadowed_fraction(light, whole_lobe), sun_visibility(s));
}
#endif
