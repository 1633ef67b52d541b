// Percentage-closer soft shadows per cell (SOFT_SHADOWS, docs/DESIGN.md §5.9): a cap of radius r_i
// shadows a receiver at depth d behind a blocker at depth d_b over a penumbra of (d - d_b) tan r_i;
// light.bias.zw turns a depth difference into tile texels. Taps on Vogel discs (radius
// sqrt((k + 0.5) / K), golden angle).
#include "shade_atlas.glsl"
#include "shade_surface.glsl"
#include "shade_tile_lookup.glsl"

const int kBlockerTaps = 8;
const vec2 kBlockerDisc[kBlockerTaps] = vec2[](vec2(0.2500, 0.0000), vec2(-0.3193, 0.2925), vec2(0.0489, -0.5569),
                                               vec2(0.4024, 0.5249), vec2(-0.7385, -0.1306), vec2(0.6996, -0.4450),
                                               vec2(-0.2340, 0.8705), vec2(-0.4463, -0.8593));
const int kFilterTaps = 12;
const vec2 kFilterDisc[kFilterTaps] = vec2[](
    vec2(0.2041, 0.0000), vec2(-0.2607, 0.2388), vec2(0.0399, -0.4547), vec2(0.3286, 0.4286), vec2(-0.6030, -0.1067),
    vec2(0.5712, -0.3634), vec2(-0.1911, 0.7107), vec2(-0.3644, -0.7016), vec2(0.7906, 0.2887), vec2(-0.8224, 0.3395),
    vec2(0.3965, -0.8472), vec2(0.2930, 0.9341));

// A per-pixel, per-light rotation of the discs: interleaved gradient noise of the pixel (deterministic:
// the same every frame and run) plus a hash of the tile's corner, so the N cells' patterns differ.
mat2 disc_rotation(Light light) {
    float noise = fract(52.9829189 * fract(dot(gl_FragCoord.xy, vec2(0.06711056, 0.00583715))));
    float angle = 6.2831853 * fract(noise + dot(light.tile.xy, vec2(7.1313, 3.7171)));
    float c = cos(angle), s = sin(angle);
    return mat2(c, s, -s, c);
}

// Cell i's soft visibility at the receiver `lookup`, whose hard 2x2 lookup is `hard`: x the whole, y the part
// of it through texels that hold no caster (the share of the search's unblocked taps that read cleared
// depth). The penumbra is sized by the blocking tap closest
// to the receiver in the tile (the discs' taps run outwards), not by the blockers' mean: the outline
// nearest the receiver is the one whose penumbra reaches it, and under an edge that rises from the ground
// (a box's vertical edge) its depth is the edge's point above the receiver, which the mean (every height
// of the edge) and the deepest blocker (its foot) both miss.
vec2 soft_visibility(Surface s, int i, TileLookup lookup, float hard) {
    Light light = lights[i];
    vec2 per_depth = light.bias.zw;
    vec2 search = per_depth * lookup.depth;  // the widest penumbra: a blocker at depth 0
    if (max(search.x, search.y) < 1.0) return vec2(hard, 0.0);
    vec2 lo = light.tile.xy + 0.5 * u_atlas_texel, hi = light.tile.xy + light.tile.zw - 0.5 * u_atlas_texel;
    vec2 slope = receiver_depth_slope(light, s.normal, 0.2);
    mat2 rotation = disc_rotation(light);
    float blockers = 0.0, closest_blocker = 0.0, empty = 0.0;
    for (int k = 0; k < kBlockerTaps; ++k) {
        vec2 offset = rotation * kBlockerDisc[k] * search;  // texels
        float z = textureLod(u_atlas_depth, clamp(lookup.unclamped + offset * u_atlas_texel, lo, hi), 0.0).r;
        if (z < lookup.depth + dot(slope, offset)) {
            if (blockers == 0.0) closest_blocker = z;
            blockers += 1.0;
        } else if (z >= 1.0) {
            empty += 1.0;
        }
    }
    if (blockers == 0.0) return vec2(hard, 0.0);
    // Every tap of the widest region a blocker, and the centre too: the (smaller) filter region is umbra.
    if (blockers == float(kBlockerTaps) && hard == 0.0) return vec2(0.0);
    vec2 radius = per_depth * max(lookup.depth - closest_blocker, 0.0);
    if (max(radius.x, radius.y) < 1.0) return vec2(hard, 0.0);  // the penumbra is under a texel
    float sum = 0.0;
    for (int k = 0; k < kFilterTaps; ++k) {
        vec2 offset = rotation * kFilterDisc[k] * radius;
        sum += plane_pcf(clamp(lookup.unclamped + offset * u_atlas_texel, lo, hi), lookup.depth + dot(slope, offset),
                         lookup.slope);
    }
    // The part through empty texels: the lit taps' share that read none in the search.
    float v = sum / float(kFilterTaps);
    return vec2(v, v * empty / max(float(kBlockerTaps) - blockers, 1.0));
}
