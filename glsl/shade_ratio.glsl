// The ratio estimator (SHADING_RATIO, docs/DESIGN.md §4.1): the unshadowed k_d E(n) + k_s S_n(r) from the
// prefiltered map (or glTF's BRDF by its split sum, docs/DESIGN.md §11), times the cells' shadowed fraction
//   L(x, w) = [k_d E(n) + k_s S_n(r)] sum_i V_i L~_i a_i / sum_i L~_i a^_i   (0 where the denominator is 0),
// a^_i with the whole specular lobe (Reflectivity.whole_lobe; glTF's BRDF: a_i itself). Without it the cells'
// sum itself.
#include "latlong.glsl"
#include "shade_metallic_roughness.glsl"
#include "shade_reflectivity.glsl"
#include "shade_surface.glsl"

// env/prefilter.h's levels: the normalised lobe S_n (n + 1) / (2 pi) on lat-long grids in map space.
layout(location = LOC_ENV_FROM_WORLD) uniform mat3 u_env_from_world;
layout(location = LOC_SPECULAR_WEIGHT) uniform float u_specular_weight;  // of the upper level, linear in log n
layout(binding = UNIT_IRRADIANCE) uniform sampler2D u_irradiance;        // level 0, n = 1: E = pi * it
layout(binding = UNIT_SPECULAR_LOWER) uniform sampler2D u_specular_lower;
layout(binding = UNIT_SPECULAR_UPPER) uniform sampler2D u_specular_upper;

// A level's rows run from pole to pole (env/prefilter.h): theta = pi j / (H - 1).
vec3 prefiltered(sampler2D level, vec2 uv) {
    float h = float(textureSize(level, 0).y);
    return textureLod(level, vec2(uv.x, (uv.y * (h - 1.0) + 0.5) / h), 0.0).rgb;
}

// The mean of the two Phong levels bound about the material's shininess at r.
vec3 lobe_mean(vec3 r) {
    vec2 uv = latlong_uv(u_env_from_world * r);
    return mix(prefiltered(u_specular_lower, uv), prefiltered(u_specular_upper, uv), u_specular_weight);
}

// Where the mirror direction turns by more than this share of the lobe's width 1 / sqrt(n) across the pixel
// (cos^n of an angle t is about exp(-n t^2 / 2)), the pixel's mean differs from its centre's value.
const float kTurnOverLobeWidth = 1.0 / 3.0;

// lobe_mean over the part of the pixel the fragment covers (pixel_footprint.glsl), as the box-filtered reference
// integrates it: where the mirror direction turns by more than kTurnOverLobeWidth across the pixel (a highlight not
// much larger than the pixel), the mean of lobe_mean at the centres of the covered quarters (of a lone covered
// quarter's own four quarters: a silhouette's sliver gets four lookups too), the normal and view at each carried
// from the centre's by their derivatives; else lobe_mean at the shaded sample's r. Quarters, not a finer grid:
// llvmpipe shades every MSAA sample, and a 4 x 4 grid where the quarters differ nearly doubled the default scene's
// shading pass (docs/DESIGN.md §4.1).
vec3 lobe_mean_over_pixel(Surface s) {
    float turn = max(length(s.pixel.mirror_dx), length(s.pixel.mirror_dy));
    if (turn * sqrt(u_shininess) <= kTurnOverLobeWidth) return lobe_mean(s.mirror);
    bool one_quarter = bitCount(s.pixel.quarters) == 1;
    vec3 sum = vec3(0.0);
    float lookups = 0.0;
    for (int q = 0; q < 4; ++q) {
        if (!covers_quarter(s.pixel, q)) continue;
        vec2 centre = vec2(q & 1, q >> 1) * 0.5 - 0.25;
        for (int k = 0; k < (one_quarter ? 4 : 1); ++k) {
            vec2 offset = one_quarter ? centre + vec2(k & 1, k >> 1) * 0.25 - 0.125 : centre;
            vec3 n = normal_at(s.pixel, offset);
            vec3 v = view_at(s.pixel, offset);
            float facing = dot(n, v);  // turned towards the viewer as shading_normal turns it
            if (facing < kFacingEpsilon) n = normalize(n + (kFacingEpsilon - facing) * v);
            sum += lobe_mean(reflect(-v, n));
            lookups += 1.0;
        }
    }
    return sum / lookups;
}

#if defined(METALLIC_ROUGHNESS)
// env/ggx_prefilter.h's levels in one texture (Renderer::set_ggx_prefiltered): level k's rows start at
// u_ggx_levels[k].x, its width and height are .y and .z; each row holds the level's row in columns 1 ... width
// with a copy of its last texel before and of its first after, so that GL_LINEAR wraps in u as GL_REPEAT
// would. Rows run from pole to pole (theta = pi j / (H - 1)), so v never reaches past the level's first or
// last row's centre. Each pixel reads the two levels about its own roughness.
layout(binding = UNIT_GGX_LEVEL_TEXELS) uniform sampler2D u_ggx_level_texels;
layout(location = LOC_GGX_LEVELS) uniform ivec3 u_ggx_levels[GGX_PREFILTER_LEVELS];
// The map itself, for lobes sharper than the sharpest level (texel centres at (j + 0.5) / H).
layout(binding = UNIT_GGX_MIRROR) uniform sampler2D u_ggx_mirror;

vec3 ggx_level(int k, vec2 uv) {
    ivec3 level = u_ggx_levels[k];
    vec2 texel = vec2(uv.x * float(level.y) + 1.0, float(level.x) + uv.y * float(level.z - 1) + 0.5);
    return textureLod(u_ggx_level_texels, texel / vec2(textureSize(u_ggx_level_texels, 0)), 0.0).rgb;
}

// P(r, alpha) at the pixel's roughness: the two levels about it, linear in log roughness
// (GgxPrefilteredEnvironment::level_pair); below the sharpest level the map itself and that level, over the
// levels' hemisphere (with a ground, nothing below the horizon), widened by the pixel's footprint.
vec3 ggx_lobe_mean(GltfPixel p, vec3 r) {
    vec2 uv = latlong_uv(u_env_from_world * r);
    if (below_levels(p)) {
        vec3 mirror = u_upper_only && r.y < 0.0 ? vec3(0.0) : textureLod(u_ggx_mirror, uv, 0.0).rgb;
        return mix(mirror, ggx_level(0, uv), mirror_level_weight(p.roughness, p.mirror_spread));
    }
    float t = clamp(5.0 * log2(p.roughness / kSharpestRoughness), 0.0, float(GGX_PREFILTER_LEVELS - 1));
    int lower = min(int(t), GGX_PREFILTER_LEVELS - 2);
    return mix(ggx_level(lower, uv), ggx_level(lower + 1, uv), t - float(lower));
}
#endif

// k_d E(n) + k_s S_n(r): the paper's BRDF integrated over the visible environment without shadows, S_n
// over the whole lobe (the cells' ratio clips it at the tangent plane); for a material with glTF's
// parameters, that BRDF's split sum instead (its lobe is whole too) and its lobe about the compact sources.
vec3 unshadowed_radiance(Surface s) {
    vec3 irradiance_over_pi = prefiltered(u_irradiance, latlong_uv(u_env_from_world * s.normal));
#if defined(METALLIC_ROUGHNESS)
    // The split sum over the map without its compact sources, and theirs with the BRDF's lobe (docs/DESIGN.md §11).
    vec3 specular = s.gltf.specular_albedo * ggx_lobe_mean(s.gltf, lobe_axis(s.gltf, s.normal, s.mirror));
    return s.gltf.diffuse_albedo * irradiance_over_pi + specular + compact_source_lobes(s);
#else
    vec3 result = s.k_d * (PI * irradiance_over_pi);
#if !defined(DIFFUSE_ONLY)
    if (u_k_s > 0.0) result += u_k_s * (2.0 * PI / (u_shininess + 1.0)) * lobe_mean_over_pixel(s);
#endif
    return result;
#endif
}

// The shadowed fraction per channel; 0 where no cell reflects (denominator 0): no cell's light reaches the point.
vec3 shadowed_fraction(vec3 shadowed, vec3 unshadowed) {
    return clamp(shadowed / max(unshadowed, vec3(1e-30)), 0.0, 1.0);
}

// The reflected radiance from the cells' sums sum_i V_i L~_i a_i (`shadowed`) and sum_i L~_i a^_i.
vec3 reflected_radiance(Surface s, vec3 shadowed, vec3 whole_lobe) {
#if defined(SHADING_RATIO)
    return unshadowed_radiance(s) * shadowed_fraction(shadowed, whole_lobe);
#else
    return shadowed;  // the paper's sum (Barsi et al. §2)
#endif
}
