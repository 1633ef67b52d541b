// The sums over the cells that shade.frag's one loop builds, and which cells that loop visits:
//   SHADOW_TILE_LISTS  every cell is summed unshadowed, and the loop takes off (1 - V) L~ a for the cells
//                      listed for the pixel's screen tile only (glsl/shadow_tiles.comp; the others see V = 1
//                      there; docs/DESIGN.md §5.5); without it the loop sums V L~ a over every cell
//   FLAT_RECEIVER      (with DIFFUSE_ONLY and SHADOW_TILE_LISTS) the unshadowed sum from u_unshadowed
#include "cells.glsl"
#include "shade_reflectivity.glsl"
#include "shade_surface.glsl"
#include "shade_visibility.glsl"

layout(location = LOC_TILES_X) uniform uint u_tiles_x;        // screen tiles per row (SHADOW_TILE_LISTS)
layout(location = LOC_UNSHADOWED) uniform vec3 u_unshadowed;  // FLAT_RECEIVER: sum of L~_i a_i, the same for every pixel

// glsl/shadow_tiles.comp: per screen tile of SCREEN_TILE^2 pixels, a count and MAX_LIGHTS indices.
layout(std430, binding = BINDING_TILE_LISTS) readonly buffer TileLists { uint tile_lists[]; };

struct CellSums {
    // sum_i V_i L~_i a_i, the paper's estimate (Barsi et al. §2); with the tile lists, until shadowed_sum(),
    // the unshadowed sum less the listed cells' shadows.
    vec3 shadowed;
    vec3 whole_lobe;  // sum_i L~_i a^_i, the ratio's denominator (docs/DESIGN.md §4.1)
};

// The cells whose shadow the loop looks up: the screen tile's list, the same for all pixels of a tile (so
// on SIMD rasterisers the loop's trip count is uniform), or every cell.
struct LookedUpCells {
    uint first;  // in tile_lists: where the tile's indices start
    uint count;
};

LookedUpCells looked_up_cells() {
#if defined(SHADOW_TILE_LISTS)
    uvec2 tile = uvec2(gl_FragCoord.xy) / uint(SCREEN_TILE);
    uint base = (tile.y * u_tiles_x + tile.x) * uint(MAX_LIGHTS + 1);
    return LookedUpCells(base + 1u, tile_lists[base]);
#else
    return LookedUpCells(0u, uint(u_light_count));
#endif
}

// The index in `lights` of the k-th cell looked up.
int cell_index(LookedUpCells cells, uint k) {
#if defined(SHADOW_TILE_LISTS)
    return int(tile_lists[cells.first + k]);
#else
    return int(k);
#endif
}

// The sums without the tile lists: V L~ a over every cell that reflects.
void add_cell(inout CellSums sums, Surface s, int i) {
    Reflectivity a = reflectivity(s, i);
    if (!reflects(a.whole_lobe)) {
        skip_cell(s, i);
        return;
    }
    sums.whole_lobe += lights[i].radiance.rgb * a.whole_lobe;
    vec3 light = lights[i].radiance.rgb * a.kept;
    if (reflects(a.kept))
        sums.shadowed += cell_visibility(s, i, light) * light;
    else
        skip_cell(s, i);
}

// With the tile lists, cell i's shadow (1 - V) L~ a taken off the unshadowed sum; a cell that reflects nothing
// is skipped without a shadow lookup.
void take_off_shadow(inout CellSums sums, Surface s, int i, vec3 light) {
    if (!reflects(light)) {
        skip_cell(s, i);
        return;
    }
    sums.shadowed -= (1.0 - cell_visibility(s, i, light)) * light;
}

void take_off_listed_shadows(inout CellSums sums, Surface s, LookedUpCells cells) {
    for (uint k = 0u; k < cells.count; ++k) {
        int i = cell_index(cells, k);
        take_off_shadow(sums, s, i, lights[i].radiance.rgb * reflectivity(s, i).kept);
    }
}

// Both sums with every cell unshadowed (V = 1).
CellSums unshadowed_sums(Surface s) {
    CellSums sums = CellSums(vec3(0.0), vec3(0.0));
    for (int i = 0; i < u_light_count; ++i) {
        Reflectivity a = reflectivity(s, i);
        sums.shadowed += lights[i].radiance.rgb * a.kept;
        sums.whole_lobe += lights[i].radiance.rgb * a.whole_lobe;
    }
    return sums;
}

// Both sums over the cells: the loop of shade.frag.
CellSums cell_sums(Surface s) {
#if defined(SOFT_SHADOWS)
    begin_penumbra_bound();
#endif
    LookedUpCells cells = looked_up_cells();
#if !defined(SHADOW_TILE_LISTS)
    CellSums sums = CellSums(vec3(0.0), vec3(0.0));
    for (uint k = 0u; k < cells.count; ++k) add_cell(sums, s, cell_index(cells, k));
#elif defined(FLAT_RECEIVER)
    // A plane with a diffuse material: its normal, hence every a_i up to the texture's factor, is constant;
    // diffuse only, there is nothing of a lobe to clip.
    vec3 unshadowed = u_unshadowed * s.base_color;
    CellSums sums = CellSums(unshadowed, unshadowed);
    take_off_listed_shadows(sums, s, cells);
#elif defined(SOFT_SHADOWS)
    // Every cell unshadowed, then the listed cells' shadows, each listed a_i evaluated again: on llvmpipe the soft
    // filter's loops inside the loop over every cell cost more than that (docs/PERFORMANCE.md, "What each
    // optimisation does").
    CellSums sums = unshadowed_sums(s);
    take_off_listed_shadows(sums, s, cells);
#else
    // Every cell unshadowed and, in the same pass, the listed cells' shadows (the list is in increasing order), so
    // that each a_i is evaluated once.
    CellSums sums = CellSums(vec3(0.0), vec3(0.0));
    uint k = 0u;
    int listed = cells.count > 0u ? cell_index(cells, 0u) : -1;  // the next cell listed
    for (int i = 0; i < u_light_count; ++i) {
        Reflectivity a = reflectivity(s, i);
        vec3 light = lights[i].radiance.rgb * a.kept;
        sums.shadowed += light;
        sums.whole_lobe += lights[i].radiance.rgb * a.whole_lobe;
        if (i == listed) {
            take_off_shadow(sums, s, i, light);
            listed = ++k < cells.count ? cell_index(cells, k) : -1;
        }
    }
#endif
    return sums;
}

// sum_i V_i L~_i a_i once the loop is done.
vec3 shadowed_sum(CellSums sums) {
#if defined(SOFT_SHADOWS)
    sums.shadowed += bounded_penumbrae();
#endif
#if defined(SHADOW_TILE_LISTS)
    return max(sums.shadowed, vec3(0.0));  // fully shadowed pixels: the difference may round below zero
#else
    return sums.shadowed;
#endif
}
