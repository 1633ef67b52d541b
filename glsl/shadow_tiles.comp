#version 450 core
// Which lights can shadow each SCREEN_TILE^2-pixel tile of the image (docs/DESIGN.md §5.5). After the
// depth pre-pass, one work group per screen tile bounds the visible receivers of its pixels in the
// world (pushed out by the largest normal offset), and lists the lights for which any of them falls
// inside the rectangle of one of the casters in that light's tile (the caster's box projected into
// the light's clip space, widened by 2 texels: the PCF footprint's reach). Everywhere else the tile
// holds cleared depth, so the visibility there is exactly 1 and shade.frag (SHADOW_TILE_LISTS,
// shade_cell_sums.glsl) skips the lookup. The list keeps the light order.
#include "cells.glsl"

layout(local_size_x = SCREEN_TILE, local_size_y = SCREEN_TILE) in;

#if defined(DEPTH_SAMPLES)
layout(binding = UNIT_DEPTH) uniform sampler2DMS u_depth;  // DEPTH_SAMPLES per pixel (MSAA)
#else
layout(binding = UNIT_DEPTH) uniform sampler2D u_depth;  // the image's depth after the pre-pass (NEAREST)
#endif
layout(location = LOC_WORLD_FROM_CLIP) uniform mat4 u_world_from_clip;
layout(location = LOC_PAD) uniform float u_pad;  // world units: the largest normal offset and rounding

layout(location = LOC_CASTER_COUNT) uniform int u_caster_count;  // rectangles per light

// Per tile: count, lights.
layout(std430, binding = BINDING_TILE_LISTS) writeonly buffer TileLists { uint tile_lists[]; };
// Per light, u_caster_count rectangles in its clip space: xy lower left, zw upper right.
layout(std430, binding = BINDING_CASTER_RECTS) readonly buffer CasterRects { vec4 caster_rects[]; };

shared uint s_lo[3], s_hi[3];
shared uint s_any;
shared uint s_needed[MAX_LIGHTS];

// Floats as uints that order like the floats (for atomicMin / atomicMax).
uint ordered(float f) {
    uint u = floatBitsToUint(f);
    return (u & 0x80000000u) != 0u ? ~u : u | 0x80000000u;
}
float unordered(uint u) {
    return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7fffffffu : ~u);
}

// Grows the tile's box by the world point at window position `xy` (pixels) and depth `depth`.
void include(vec2 xy, vec2 size, float depth) {
    vec4 ndc = vec4(xy / size * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
    vec4 world = u_world_from_clip * ndc;
    vec3 p = world.xyz / world.w;
    for (int c = 0; c < 3; ++c) {
        atomicMin(s_lo[c], ordered(p[c]));
        atomicMax(s_hi[c], ordered(p[c]));
    }
}

void main() {
    uint local = gl_LocalInvocationIndex;
    if (local < 3u) {
        s_lo[local] = 0xffffffffu;
        s_hi[local] = 0u;
    }
    if (local == 0u) s_any = 0u;
    barrier();

    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
#if defined(DEPTH_SAMPLES)
    ivec2 size = textureSize(u_depth);
    if (all(lessThan(pixel, size))) {
        // The samples lie anywhere in the pixel (and shade.frag shades at one of them, centroid): the
        // pixel's frustum between its nearest and farthest object sample holds them all, and it is the hull
        // of its 8 corners (clip to world is affine across a plane of constant depth).
        float nearest = 1.0, farthest = 0.0;
        for (int k = 0; k < DEPTH_SAMPLES; ++k) {
            float depth = texelFetch(u_depth, pixel, k).r;
            if (depth < 1.0) {  // an object (the background keeps the cleared depth 1)
                nearest = min(nearest, depth);
                farthest = max(farthest, depth);
            }
        }
        if (nearest < 1.0) {
            for (int corner = 0; corner < 8; ++corner)
                include(vec2(pixel + ivec2(corner & 1, (corner >> 1) & 1)), vec2(size),
                        (corner & 4) != 0 ? farthest : nearest);
            s_any = 1u;
        }
    }
#else
    ivec2 size = textureSize(u_depth, 0);
    if (all(lessThan(pixel, size))) {
        float depth = texelFetch(u_depth, pixel, 0).r;
        if (depth < 1.0) {  // an object (the background keeps the cleared depth 1)
            include(vec2(pixel) + 0.5, vec2(size), depth);
            s_any = 1u;
        }
    }
#endif
    barrier();

    uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint base = tile * uint(MAX_LIGHTS + 1);
    if (s_any == 0u) {
        if (local == 0u) tile_lists[base] = 0u;
        return;
    }
    vec3 lo = vec3(unordered(s_lo[0]), unordered(s_lo[1]), unordered(s_lo[2])) - u_pad;
    vec3 hi = vec3(unordered(s_hi[0]), unordered(s_hi[1]), unordered(s_hi[2])) + u_pad;
    for (uint i = local; i < uint(u_light_count); i += uint(SCREEN_TILE * SCREEN_TILE)) {
        // The box's corners in the light's clip space; the box lies outside the tile where all
        // corners are beyond one side.
        vec2 clip_lo = vec2(1e30), clip_hi = vec2(-1e30);
        for (int k = 0; k < 8; ++k) {
            vec3 corner = vec3((k & 1) != 0 ? hi.x : lo.x, (k & 2) != 0 ? hi.y : lo.y, (k & 4) != 0 ? hi.z : lo.z);
            vec2 c = (lights[i].clip_from_world * vec4(corner, 1.0)).xy;
            clip_lo = min(clip_lo, c);
            clip_hi = max(clip_hi, c);
        }
        uint needed = 0u;
        for (int c = 0; c < u_caster_count; ++c) {
            vec4 rect = caster_rects[int(i) * u_caster_count + c];
            if (all(lessThanEqual(clip_lo, rect.zw)) && all(greaterThanEqual(clip_hi, rect.xy))) needed = 1u;
        }
        s_needed[i] = needed;
    }
    barrier();
    if (local == 0u) {
        uint count = 0u;
        for (uint i = 0u; i < uint(u_light_count); ++i)
            if (s_needed[i] != 0u) tile_lists[base + 1u + count++] = i;
        tile_lists[base] = count;
    }
}
