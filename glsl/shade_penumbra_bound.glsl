// The soft shadows' bound (SOFT_SHADOWS, docs/DESIGN.md §5.9). The taps of one tile past a caster's
// outline read no caster whether a wall stands hidden under a roof's edge (a room) or nothing does (a car
// port), so the light of such taps reaches a point that the cell's centre does not see only where the
// centre of a cell of its neighbourhood (engine/render/lights.h) does. Which centres see the point is known
// once the loop over the cells is done, so that light waits until then: that of up to kDeferredPenumbrae
// cells, each with its cell, and that of the rest together, bounded by any centre seeing the point.
#include "cells.glsl"

const int kDeferredPenumbrae = 16;

// Bit i % 32 of seen_centres[i / 32]: cell i's centre may see the point. Cleared for the cells looked up
// whose centre does not (centre_sees) and for those under the tangent plane; the cells the loop does not
// look up (no caster over the screen tile) keep theirs.
uint seen_centres[MAX_LIGHTS / 32];
int deferred_count;
int deferred_cell[kDeferredPenumbrae];
vec3 deferred_light[kDeferredPenumbrae];  // the held-back part of V, times L~ a, of each
vec3 overflow_light;                      // of those beyond kDeferredPenumbrae

void begin_penumbra_bound() {
    for (int w = 0; w < MAX_LIGHTS / 32; ++w) seen_centres[w] = ~0u;
    deferred_count = 0;
    overflow_light = vec3(0.0);
}

void centre_unseen(int i) {
    seen_centres[i >> 5] &= ~(1u << uint(i & 31));
}

void unseen_under_the_plane(int i) {
#if defined(SOFT_SHADOWS)
    centre_unseen(i);
#endif
}

// Whether cell i's centre sees the point: above the tangent plane, and its hard lookup `hard` on the lit
// side of the lookup's bilinear edge.
bool centre_sees(float cos_theta, float hard) {
    return cos_theta > 0.0 && hard >= 0.5;
}

// Cell i's visibility for the loop's sums from its soft visibility v (x the whole, y the part through taps
// that read no caster), whether its centre sees the point and `light` = L~_i a_i. Where the centre does
// not, the part through empty texels counts 0 until bounded_penumbrae() finds the cell a seeing neighbour;
// light through an opening in a caster (taps that read a surface behind the receiver's plane) stays.
float bounded_visibility(int i, bool centre_seen, vec2 v, vec3 light) {
    if (centre_seen) return v.x;
    centre_unseen(i);
    if (v.y == 0.0 || lights[i].radiance.w == 0.0) return v.x;  // nothing held back; no neighbours around
    if (deferred_count < kDeferredPenumbrae) {
        deferred_cell[deferred_count] = i;
        deferred_light[deferred_count] = v.y * light;
        ++deferred_count;
    } else {
        overflow_light += v.y * light;
    }
    return v.x - v.y;
}

bool neighbourhood_sees(int i) {
    uint seen = 0u;
    for (int w = 0; w < (u_light_count + 31) / 32; ++w) seen |= lights[i].neighbourhood[w >> 2][w & 3] & seen_centres[w];
    return seen != 0u;
}

// The deferred penumbrae that some centre of their cell's neighbourhood sees (the rest: any centre).
vec3 bounded_penumbrae() {
    vec3 sum = vec3(0.0);
    for (int k = 0; k < deferred_count; ++k)
        if (neighbourhood_sees(deferred_cell[k])) sum += deferred_light[k];
    uint any_seen = 0u;
    int words = (u_light_count + 31) / 32;
    for (int w = 0; w < words; ++w) {
        int in_word = u_light_count - 32 * w;  // lights in this word: the last may hold fewer than 32
        any_seen |= seen_centres[w] & (in_word >= 32 ? ~0u : (1u << uint(in_word)) - 1u);
    }
    return any_seen != 0u ? sum + overflow_light : sum;
}
