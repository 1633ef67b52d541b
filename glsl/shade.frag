#version 450 core
// Reflected radiance of the environment with shadows (Barsi et al. §2):
//   L(x, w) ~ sum_i V(x, w_i) L~_i a(dw_i, w),  a = k_d (cos theta average) + k_s (a_s / k_s)
// V from the cell's tile in the shadow atlas (hardware depth comparison, PCF), L~_i and the cap
// from the light record. Options (engine/render/renderer.cpp sets them as #defines):
//   DIFFUSE_CAP      clamped cosine averaged over the cell's cap instead of the centre sample
//   SPECULAR_SINGLE  the single sample k_s cos^n psi_c instead of the blended average
//   PCF_WIDE         3x3 hardware-filtered taps (a 4x4 texel footprint) instead of one (2x2)
//   SHADOW_TILE_LISTS shadow lookups only for the lights listed for the pixel's screen tile
//   FLAT_RECEIVER    (with DIFFUSE_ONLY and SHADOW_TILE_LISTS) the unshadowed sum from u_unshadowed
//   DIFFUSE_ONLY     for materials with k_s = 0: the specular code left out (a uniform branch on
//                    u_k_s still costs its whole body on SIMD CPU rasterisers such as llvmpipe)
//   SOFT_SHADOWS     each cell's penumbra from its cap (percentage-closer soft shadows, docs/DESIGN.md §5.9)
//   SHADING_RATIO    the ratio estimator (docs/DESIGN.md §4.1): the unshadowed k_d E(n) + k_s S_n(r) from
//                    the prefiltered map, times the cells' shadowed fraction sum V L~ a / sum L~ a
#include "cells.glsl"
#include "brdf.glsl"
#if defined(SHADING_RATIO)
#include "latlong.glsl"
#endif

// centroid: with MSAA, interpolated inside the triangle (at a covered sample) rather than at the pixel
// centre, which may lie beyond a silhouette edge; the same as the centre at one sample per pixel.
layout(location = 0) centroid in vec3 v_world_position;
layout(location = 1) centroid in vec3 v_world_normal;
layout(location = 2) centroid in vec2 v_texcoord;

layout(location = LOC_EYE) uniform vec3 u_eye;
layout(location = LOC_LIGHT_COUNT) uniform int u_light_count;
layout(location = LOC_ATLAS_TEXEL) uniform vec2 u_atlas_texel;  // size of one atlas texel in uv
layout(location = LOC_SLOPE_BIAS) uniform float u_slope_bias;   // extra depth bias, texels of the plane's slope
vec3 plane_normal;  // the triangle's normal (either side) at this pixel: main() sets it first
layout(location = LOC_K_D) uniform vec3 u_k_d;                  // rho_d / pi
// The base-colour texture (linear: an sRGB texture), white without one; it scales k_d at each pixel.
layout(binding = UNIT_BASE_COLOR) uniform sampler2D u_base_color;
vec3 k_d;  // u_k_d times the texture at this pixel: main() sets it first
layout(location = LOC_K_S) uniform float u_k_s;                 // rho_s (n + 2) / (2 pi)
layout(location = LOC_SHININESS) uniform float u_shininess;

layout(location = LOC_TILES_X) uniform uint u_tiles_x;  // screen tiles per row (SHADOW_TILE_LISTS)
layout(location = LOC_UNSHADOWED) uniform vec3 u_unshadowed;  // FLAT_RECEIVER: sum of L~_i a_i, the same for every pixel

layout(binding = UNIT_ATLAS_DEPTH) uniform sampler2D u_atlas_depth;  // the atlas's depths (NEAREST)

#if defined(SHADING_RATIO)
// env/prefilter.h's levels: the normalised lobe S_n (n + 1) / (2 pi) on lat-long grids in map space.
layout(location = LOC_ENV_FROM_WORLD) uniform mat3 u_env_from_world;
layout(location = LOC_SPECULAR_WEIGHT) uniform float u_specular_weight;  // of the upper level, linear in log n
layout(binding = UNIT_IRRADIANCE) uniform sampler2D u_irradiance;        // level 0, n = 1: E = pi * it
layout(binding = UNIT_SPECULAR_LOWER) uniform sampler2D u_specular_lower;
layout(binding = UNIT_SPECULAR_UPPER) uniform sampler2D u_specular_upper;

// A level's rows run from pole to pole (env/prefilter.h): theta = pi j / (H - 1).
vec3 prefiltered(sampler2D level, vec2 uv) {
    float h = float(textureSize(level, 0).y);
    return texture(level, vec2(uv.x, (uv.y * (h - 1.0) + 0.5) / h)).rgb;
}

// k_d E(n) + k_s S_n(r): the paper's BRDF integrated over the visible environment without shadows, S_n
// over the whole lobe (the cells' ratio clips it at the tangent plane: reflectivity's whole_lobe).
vec3 unshadowed_radiance(vec3 n, vec3 mirror) {
    vec3 result = k_d * (PI * prefiltered(u_irradiance, latlong_uv(u_env_from_world * n)));
#if !defined(DIFFUSE_ONLY)
    if (u_k_s > 0.0) {
        vec2 uv = latlong_uv(u_env_from_world * mirror);
        vec3 mean = mix(prefiltered(u_specular_lower, uv), prefiltered(u_specular_upper, uv), u_specular_weight);
        result += u_k_s * (2.0 * PI / (u_shininess + 1.0)) * mean;
    }
#endif
    return result;
}

// The shadowed fraction per channel, 1 where no cell reflects (denominator 0).
vec3 shadowed_fraction(vec3 shadowed, vec3 unshadowed) {
    return mix(vec3(1.0), clamp(shadowed / max(unshadowed, vec3(1e-30)), 0.0, 1.0), greaterThan(unshadowed, vec3(0.0)));
}
#endif

#if defined(SHADOW_TILE_LISTS)
// glsl/shadow_tiles.comp: per screen tile of SCREEN_TILE^2 pixels, a count and MAX_LIGHTS indices.
layout(std430, binding = BINDING_TILE_LISTS) readonly buffer TileLists { uint tile_lists[]; };
#endif

layout(location = 0) out vec4 o_color;

#if defined(PCF_WIDE) && !defined(SOFT_SHADOWS)
const float kKernelTexels = 1.5;  // tap offsets of 1 texel plus the 2x2 bilinear footprint
#else
const float kKernelTexels = 0.5;
#endif
// The receiver-plane depth bias's slopes are clamped at 50 texels of depth per texel (the plane's normal
// at least 0.02 off the tile's plane in clip space): more than 5, the soft shadows' clamp, since a convex
// receiver near its terminator (a sphere under N = 1) would otherwise shadow itself.
const float kPlaneBiasMinNormalZ = 0.02;

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

// The hardware's 2x2 PCF (bilinear weights of the four texels around uv), but each texel compared with the
// receiver's plane carried to that texel's centre, depth + slope . (centre - uv), rather than with one
// depth for all four: no texel of the receiver's own plane shadows it, with no bias growing with the
// slope, so a blocker a few texels away across a concave corner (a wall meeting a roof) still shadows.
float plane_pcf(vec2 uv, float depth, vec2 slope) {
    vec2 texel = uv / u_atlas_texel - 0.5;  // texel centres at integers
    vec2 corner = floor(texel);
    vec2 f = texel - corner;
    // textureGather at the shared corner of the four: (0, 1), (1, 1), (1, 0), (0, 0).
    vec4 stored = textureGather(u_atlas_depth, (corner + 1.0) * u_atlas_texel);
    vec4 dx = vec4(-f.x, 1.0 - f.x, 1.0 - f.x, -f.x), dy = vec4(1.0 - f.y, 1.0 - f.y, -f.y, -f.y);
    vec4 lit = vec4(lessThanEqual(min(depth + slope.x * dx + slope.y * dy, 1.0), stored));
    return mix(mix(lit.w, lit.z, f.x), mix(lit.x, lit.y, f.x), f.y);
}

#if defined(SOFT_SHADOWS)
// Percentage-closer soft shadows per cell (docs/DESIGN.md §5.9): a cap of radius r_i shadows a receiver
// at depth d behind a blocker at depth d_b over a penumbra of (d - d_b) tan r_i; light.bias.zw turns a
// depth difference into tile texels. Taps on Vogel discs (radius sqrt((k + 0.5) / K), golden angle).
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

// uv: the receiver's (unclamped) position in the atlas, depth: its biased depth, hard: the 2x2 lookup there.
// plane_slope: the triangle's, for plane_pcf.
float soft_visibility(Light light, vec3 n, vec2 uv, float depth, float hard, vec2 plane_slope) {
    vec2 per_depth = light.bias.zw;
    vec2 search = per_depth * depth;  // the widest penumbra: a blocker at depth 0
    if (max(search.x, search.y) < 1.0) return hard;
    vec2 lo = light.tile.xy + 0.5 * u_atlas_texel, hi = light.tile.xy + light.tile.zw - 0.5 * u_atlas_texel;
    vec2 slope = receiver_depth_slope(light, n, 0.2);
    mat2 rotation = disc_rotation(light);
    float blockers = 0.0, nearest_blocker = 0.0;  // the blocker nearest the receiver: the largest depth
    for (int k = 0; k < kBlockerTaps; ++k) {
        vec2 offset = rotation * kBlockerDisc[k] * search;  // texels
        float z = textureLod(u_atlas_depth, clamp(uv + offset * u_atlas_texel, lo, hi), 0.0).r;
        if (z < depth + dot(slope, offset)) blockers += 1.0, nearest_blocker = max(nearest_blocker, z);
    }
    if (blockers == 0.0) return hard;
    // Every tap of the widest region a blocker, and the centre too: the (smaller) filter region is umbra.
    if (blockers == float(kBlockerTaps) && hard == 0.0) return 0.0;
    vec2 radius = per_depth * max(depth - nearest_blocker, 0.0);
    if (max(radius.x, radius.y) < 1.0) return hard;  // the penumbra is under a texel
    float sum = 0.0;
    for (int k = 0; k < kFilterTaps; ++k) {
        vec2 offset = rotation * kFilterDisc[k] * radius;
        sum += plane_pcf(clamp(uv + offset * u_atlas_texel, lo, hi), depth + dot(slope, offset), plane_slope);
    }
    return sum / float(kFilterTaps);
}
#endif

// Fraction of the cell's shadow map that sees `p`. Each texel the filter reads is compared with the
// receiver's triangle's plane carried to that texel (plane_pcf, docs/DESIGN.md §5.3), so no texel of its
// own plane shadows it; the receiver's depth is lowered by the depth bias, which covers the casters' level
// of detail (at most 0.3 texel off), and by u_slope_bias texels of its plane's slope (0 by default). It may
// also be moved along its normal by the light's normal offset (more at grazing angles; 0 by default).
// Lookups are clamped to the tile's interior so no tap reads a neighbouring tile; casters keep a margin
// from the tile's border, so a receiver outside the tile reads cleared depth and is lit. Receivers beyond
// the far plane compare at the far plane: shadowed where any caster is above them.
float visibility(Light light, vec3 p, vec3 n, float cos_theta) {
    float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    vec3 q = p + n * (light.bias.y * max(sin_theta, 0.2));
    vec4 clip = light.clip_from_world * vec4(q, 1.0);
    vec2 margin = kKernelTexels * u_atlas_texel;
    vec2 unclamped = light.tile.xy + (0.5 * clip.xy + 0.5) * light.tile.zw;
    vec2 uv = clamp(unclamped, light.tile.xy + margin, light.tile.xy + light.tile.zw - margin);
    vec2 slope = receiver_depth_slope(light, plane_normal, kPlaneBiasMinNormalZ);
    float plane_bias = u_slope_bias * (abs(slope.x) + abs(slope.y));
    // A triangle turned away from the light while its shading normal is not (a coarse sphere's
    // terminator) is not itself in the atlas, and one within the slope clamp of grazing has a plane steeper
    // than the carried one: there the four texels are compared with one depth lowered by the plane's bound
    // over the footprint, as a convex neighbour nearer the light would otherwise shadow it.
    if (dot(plane_normal, n) * dot(plane_normal, light.direction.xyz) <= kPlaneBiasMinNormalZ) {
        plane_bias += (kKernelTexels + 0.5) * (abs(slope.x) + abs(slope.y));
        slope = vec2(0.0);
    }
    float depth = min(0.5 * clip.z + 0.5 - light.bias.x - plane_bias, 1.0);
#if defined(SOFT_SHADOWS)
    return soft_visibility(light, n, unclamped, depth, plane_pcf(uv, depth, slope), slope);
#elif defined(PCF_WIDE)
    float sum = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
            sum += plane_pcf(uv + vec2(x, y) * u_atlas_texel, depth + dot(slope, vec2(x, y)), slope);
    return sum / 9.0;
#else
    return plane_pcf(uv, depth, slope);
#endif
}

#if defined(SHADING_RATIO)
// Standard normal cumulative distribution: erf by Abramowitz and Stegun 7.1.26 (|error| < 1.5e-7).
float normal_cdf(float x) {
    float z = abs(x) * 0.70710678;
    float t = 1.0 / (1.0 + 0.3275911 * z);
    float erf_z = 1.0 - t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429)))) * exp(-z * z);
    return 0.5 + 0.5 * sign(x) * erf_z;
}

// Elevation above the tangent plane of a direction whose cosine with the normal is c: asin c (by atan,
// which llvmpipe evaluates more precisely than asin).
float elevation(float c) {
    c = clamp(c, -1.0, 1.0);
    return atan(c, sqrt((1.0 - c) * (1.0 + c)));
}

// Part of the lobe inside the cell's cap that lies above the tangent plane (docs/DESIGN.md §4.1), from the
// elevations of the mirror direction and of the cap's centre: with the lobe cos^n psi ~ exp(-n psi^2 / 2)
// and the cap (a disc of radius r, whose elevation has variance r^2 / 4) as Gaussians, their product's
// elevation is Gaussian with precision n + 4 / r^2 and the precision-weighted mean of the two; its part
// above zero is the normal distribution's. A lobe narrower than the cell is clipped where it is, a
// cell smaller than the lobe by the part of it above the plane.
float lobe_part_above(float cos_mirror, float cos_centre, float cos_r, float n) {
    float r = precise_acos(cos_r);
    float lobe_precision = n, cap_precision = 4.0 / max(r * r, 1e-12);
    float precision_sum = lobe_precision + cap_precision;
    float mean = (lobe_precision * elevation(cos_mirror) + cap_precision * elevation(cos_centre)) / precision_sum;
    return normal_cdf(mean * sqrt(precision_sum));
}
#endif

// a(dw_i, w) of light i: k_d times the cosine term plus k_s times the specular average, which is zero
// for a cell whose centre is under the tangent plane (in ratio shading: times the part of the lobe in the
// cell's cap above it). `whole_lobe` hears the same with the whole specular term kept (the ratio's denominator,
// below), computed in the same pass.
#define CLIP_COS_RADIUS 0.9
vec3 reflectivity(int i, vec3 n, vec3 mirror, out vec3 whole_lobe) {
    vec3 w = lights[i].direction.xyz;
    float cos_r = lights[i].direction.w;
    float cos_theta = dot(n, w);
#if defined(DIFFUSE_CAP)
    float diffuse = average_clamped_cosine(cos_theta, cos_r);
#else
    float diffuse = max(cos_theta, 0.0);  // the paper's centre sample, a_d = k_d cos theta_c
#endif
#if defined(SHADING_RATIO)
    bool needed = true;  // the whole lobe is wanted too
#else
    bool clipped = cos_theta <= 0.0;  // the BRDF is zero under the tangent plane (docs/DESIGN.md §2)
    bool needed = !clipped;
#endif
    float specular = 0.0;
#if !defined(DIFFUSE_ONLY)
    if (u_k_s > 0.0 && needed) {
#if defined(SPECULAR_SINGLE)
        specular = average_specular_single(dot(w, mirror), u_shininess);
#else
        specular = average_specular_blended(dot(w, mirror), cos_r, u_shininess);
#endif
    }
#endif
    whole_lobe = k_d * diffuse + u_k_s * specular;
#if defined(SHADING_RATIO)
    // The BRDF is zero under the tangent plane (docs/DESIGN.md §2): a cell near it keeps the part of its
    // lobe above it (§4.1), rather than all or nothing by its centre; a cell too large to clip (its cap
    // wider than acos CLIP_COS_RADIUS) keeps all of it.
    if (cos_r < CLIP_COS_RADIUS) return whole_lobe;
    return k_d * diffuse + u_k_s * specular * lobe_part_above(dot(n, mirror), cos_theta, cos_r, u_shininess);
#else
    return clipped ? k_d * diffuse : whole_lobe;
#endif
}

vec3 reflectivity(int i, vec3 n, vec3 mirror) {
    vec3 whole_lobe;
    return reflectivity(i, n, mirror, whole_lobe);
}

#if defined(SHADING_RATIO)
// The ratio's denominator estimates what the prefiltered map holds: S_n(r) covers the whole lobe, the BRDF
// only the half above the tangent plane. With the whole lobe below the line and the clipped one above it,
// the ratio takes off the part of the lobe under the surface as well as the shadows, weighted by where the
// light really is (a sun inside the kept half keeps all of it); it matters where r grazes the surface
// (docs/DESIGN.md §4.1).

// A cell too large to clip (its cap wider than acos CLIP_COS_RADIUS) keeps its whole lobe above the line
// too; where its centre is under the tangent plane its shadow lookup means nothing, and it counts as lit.
float cell_visibility(int i, vec3 p, vec3 n) {
    float cos_theta = dot(n, lights[i].direction.xyz);
    return cos_theta > 0.0 ? visibility(lights[i], p, n, cos_theta) : 1.0;
}
#endif

// Shading normal at p (docs/DESIGN.md §5.4). The side comes from the triangle: seen from behind (an open
// mesh), the normal is turned round; the interpolated normal itself may still face away from the viewer
// near a silhouette, and is then bent towards the viewer in the plane of n and v until n.v is about
// kFacingEpsilon (turning it round instead would point it into the surface: a black rim): a simpler form
// of Iray's shading normal adaptation (Keller et al. 2017). The reference (engine/reference/reference.cpp)
// does the same.
const float kFacingEpsilon = 0.01;
vec3 shading_normal(vec3 interpolated, vec3 view) {
    vec3 n = gl_FrontFacing ? interpolated : -interpolated;
    float facing = dot(n, view);
    if (facing < kFacingEpsilon) n = normalize(n + (kFacingEpsilon - facing) * view);
    return n;
}

void main() {
    vec3 base_color = texture(u_base_color, v_texcoord).rgb;
    k_d = u_k_d * base_color;
    vec3 p = v_world_position;
    vec3 view = normalize(u_eye - p);
    vec3 n = shading_normal(normalize(v_world_normal), view);
    // The plane of the triangle, from the position's screen derivatives (helper invocations interpolate
    // the same triangle): the surface the atlas holds, which the interpolated normal only approximates.
    // A triangle seen edge on has none: its shading normal stands in.
    vec3 across = cross(dFdx(p), dFdy(p));
    plane_normal = dot(across, across) > 0.0 ? normalize(across) : n;
    vec3 mirror = reflect(-view, n);

    vec3 radiance = vec3(0.0);
#if defined(SHADOW_TILE_LISTS)
    // Every light unshadowed, then the shadow taken off for the lights listed for this screen tile
    // (glsl/shadow_tiles.comp): the others see V = 1 here. The lists are the same for all pixels of a
    // tile, so on SIMD rasterisers the second loop's trip count is uniform.
#if defined(FLAT_RECEIVER)
    // A plane with a diffuse material: its normal, hence every a_i up to the texture's factor, is constant.
    vec3 unshadowed = u_unshadowed * base_color;
#else
    vec3 unshadowed = vec3(0.0);
#if defined(SHADING_RATIO)
    vec3 whole_lobe = vec3(0.0);
    for (int i = 0; i < u_light_count; ++i) {
        vec3 whole;
        unshadowed += lights[i].radiance.rgb * reflectivity(i, n, mirror, whole);
        whole_lobe += lights[i].radiance.rgb * whole;
    }
#else
    for (int i = 0; i < u_light_count; ++i) unshadowed += lights[i].radiance.rgb * reflectivity(i, n, mirror);
#endif
#endif
    radiance = unshadowed;
    uvec2 tile = uvec2(gl_FragCoord.xy) / uint(SCREEN_TILE);
    uint base = (tile.y * u_tiles_x + tile.x) * uint(MAX_LIGHTS + 1);
    uint count = tile_lists[base];
    for (uint k = 0u; k < count; ++k) {
        int i = int(tile_lists[base + 1u + k]);
        vec3 a = reflectivity(i, n, mirror);
        if (max(a.r, max(a.g, a.b)) <= 0.0) continue;  // no reflection: skip the shadow lookups
#if defined(SHADING_RATIO)
        radiance -= (1.0 - cell_visibility(i, p, n)) * lights[i].radiance.rgb * a;
#else
        radiance -= (1.0 - visibility(lights[i], p, n, dot(n, lights[i].direction.xyz))) * lights[i].radiance.rgb * a;
#endif
    }
    radiance = max(radiance, vec3(0.0));  // fully shadowed pixels: the difference may round below zero
#if defined(SHADING_RATIO)
#if defined(FLAT_RECEIVER)
    vec3 whole_lobe = unshadowed;  // diffuse only: nothing of a lobe to clip
#endif
    radiance = unshadowed_radiance(n, mirror) * shadowed_fraction(radiance, whole_lobe);
#endif
#elif defined(SHADING_RATIO)
    // Numerator and denominator of the ratio in the one loop over the cells.
    vec3 shadowed = vec3(0.0), whole_lobe = vec3(0.0);
    for (int i = 0; i < u_light_count; ++i) {
        vec3 whole;
        vec3 a = reflectivity(i, n, mirror, whole);
        if (max(whole.r, max(whole.g, whole.b)) <= 0.0) continue;
        whole_lobe += lights[i].radiance.rgb * whole;
        if (max(a.r, max(a.g, a.b)) > 0.0) shadowed += cell_visibility(i, p, n) * lights[i].radiance.rgb * a;
    }
    radiance = unshadowed_radiance(n, mirror) * shadowed_fraction(shadowed, whole_lobe);
#else
    for (int i = 0; i < u_light_count; ++i) {
        vec3 a = reflectivity(i, n, mirror);
        if (max(a.r, max(a.g, a.b)) <= 0.0) continue;  // no reflection: skip the shadow lookups
        radiance += visibility(lights[i], p, n, dot(n, lights[i].direction.xyz)) * lights[i].radiance.rgb * a;
    }
#endif
    o_color = vec4(radiance, 1.0);  // alpha 1 marks object pixels (the accuracy comparison masks by it)
}
