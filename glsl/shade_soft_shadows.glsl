// Percentage-closer soft shadows per cell (SOFT_SHADOWS, docs/DESIGN.md §5.9): a cap of radius r_i
// shadows a receiver at depth d behind a blocker at depth d_b over a penumbra of (d - d_b) tan r_i;
// light.bias.zw turns a depth difference into tile texels.
#include "shade_atlas.glsl"
#include "shade_surface.glsl"
#include "shade_tile_lookup.glsl"

const int kBlockerTaps = 8;
const int kFilterTaps = 12;

// Vogel discs: tap k of K at radius sqrt((k + 0.5) / K), k golden angles round from a first direction. The
// taps are made by one rotation each, not read from constant arrays: llvmpipe keeps an array indexed by the
// loop's counter in memory, which made the soft shadows' lookups half as long again (docs/PERFORMANCE.md).
const mat2 kGoldenAngle = mat2(-0.7373688, 0.6754903, -0.6754903, -0.7373688);  // 137.508 degrees

// The next tap of a disc of `taps` (the k-th) and the direction of the one after it.
vec2 vogel_tap(inout vec2 direction, int k, int taps) {
    vec2 tap = direction * sqrt((float(k) + 0.5) / float(taps));
    direction = kGoldenAngle * direction;
    return tap;
}

// The discs' first direction, per pixel and per light: interleaved gradient noise of the pixel
// (deterministic: the same every frame and run) plus a hash of the tile's corner, so the N cells' patterns
// differ.
vec2 disc_direction(Light light) {
    float noise = fract(52.9829189 * fract(dot(gl_FragCoord.xy, vec2(0.06711056, 0.00583715))));
    float angle = 6.2831853 * fract(noise + dot(light.tile.xy, vec2(7.1313, 3.7171)));
    return vec2(cos(angle), sin(angle));
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
    vec2 first_direction = disc_direction(light);
    vec2 direction = first_direction;
    float blockers = 0.0, closest_blocker = 0.0, empty = 0.0;
    for (int k = 0; k < kBlockerTaps; ++k) {
        vec2 offset = vogel_tap(direction, k, kBlockerTaps) * search;  // texels
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
    // Each tap is a direction of the cap, w + tan r (t.x e_x + t.y e_y) for the tap t of the unit disc and the
    // tile's axes e_x, e_y, weighted by the receiver's cosine there: where an edge cuts the cap, the part it
    // leaves lies to one side of w, and its cosine is not w's.
    float cos_r = light.direction.w;
    float tan_r = sqrt(max(1.0 - cos_r * cos_r, 0.0)) / max(cos_r, 1e-4);
    mat3 m = mat3(light.clip_from_world);
    vec2 lateral = tan_r * vec2(dot(s.normal, normalize(vec3(m[0][0], m[1][0], m[2][0]))),
                                dot(s.normal, normalize(vec3(m[0][1], m[1][1], m[2][1]))));
    float cos_w = dot(s.normal, light.direction.xyz);
    float sum = 0.0, weights = 0.0;
    direction = first_direction;
    for (int k = 0; k < kFilterTaps; ++k) {
        vec2 tap = vogel_tap(direction, k, kFilterTaps);
        vec2 offset = tap * radius;
        float weight = max(cos_w + dot(tap, lateral), 0.0);
        sum += weight * plane_pcf(clamp(lookup.unclamped + offset * u_atlas_texel, lo, hi),
                                  lookup.depth + dot(slope, offset), lookup.slope);
        weights += weight;
    }
    // The part through empty texels: the lit taps' share that read none in the search.
    float v = weights > 0.0 ? sum / weights : 0.0;
    return vec2(v, v * empty / max(float(kBlockerTaps) - blockers, 1.0));
}
