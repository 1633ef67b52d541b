// a(dw_i, w) = k_d a_d + k_s a_s of each cell at the shaded surface (Barsi et al. §2.3, docs/DESIGN.md §4):
//   DIFFUSE_CAP      a_d: the clamped cosine averaged over the cell's cap instead of the centre sample
//   SPECULAR_SINGLE  a_s: the single sample cos^n psi_c instead of the blended average
//   DIFFUSE_ONLY     for materials with k_s = 0: the specular code left out (a uniform branch on u_k_s
//                    still costs its whole body on SIMD CPU rasterisers such as llvmpipe)
//   SHADING_RATIO    the ratio estimator's clipping at the tangent plane (docs/DESIGN.md §4.1)
//   METALLIC_ROUGHNESS (with SHADING_RATIO) glTF's BRDF in place of the paper's, and its compact lights'
//                    correction of the split sum (docs/DESIGN.md §11)
#include "brdf.glsl"
#include "cells.glsl"
#include "shade_surface.glsl"

struct Reflectivity {
    // a_i: zero under the tangent plane, where the BRDF is (docs/DESIGN.md §2).
    vec3 kept;
    // The same with the whole specular lobe kept (the ratio's denominator, docs/DESIGN.md §4.1). Cells
    // shading does not evaluate the lobe of a cell whose centre is under the plane: there it equals `kept`.
    vec3 whole_lobe;
};

bool reflects(vec3 a) {
    return max(a.r, max(a.g, a.b)) > 0.0;
}

// a_d: the paper's centre sample max(0, cos theta_c), or the exact average over the cap (DIFFUSE_CAP).
float diffuse_average(float cos_theta, float cos_r) {
#if defined(DIFFUSE_CAP)
    return average_clamped_cosine(cos_theta, cos_r);
#else
    return max(cos_theta, 0.0);
#endif
}

// a_s / k_s for c = cos psi_c between the mirror direction and the cell's centre: the paper's blended
// average, or the single sample (SPECULAR_SINGLE); nothing for a diffuse-only material (DIFFUSE_ONLY).
float specular_average(float cos_psi_c, float cos_r) {
#if defined(DIFFUSE_ONLY)
    return 0.0;
#elif defined(SPECULAR_SINGLE)
    return average_specular_single(cos_psi_c, u_shininess);
#else
    return average_specular_blended(cos_psi_c, cos_r, u_shininess);
#endif
}

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

// A cell whose cap is wider than acos kClipCosRadius is too coarse to clip (docs/DESIGN.md §4.1).
const float kClipCosRadius = 0.9;

bool under_tangent_plane(float cos_theta) {
    return cos_theta <= 0.0;
}

// Whether a cell's specular average is needed: cells shading drops the lobe of a cell whose centre is
// under the tangent plane, so it is not evaluated there; the ratio wants every cell's whole lobe.
bool specular_needed(float cos_theta) {
#if defined(SHADING_RATIO)
    return true;
#else
    return !under_tangent_plane(cos_theta);
#endif
}

// a_i from its parts k_d a_d and k_s a_s, clipped at the tangent plane (docs/DESIGN.md §2): all or nothing
// of the specular part by the cell's centre, as in the paper; in ratio shading the part of the lobe in the
// cell's cap above the plane (§4.1), all of it for a cell too coarse to clip.
vec3 clipped_reflectivity(vec3 diffuse_part, float specular_part, Surface s, float cos_theta, float cos_r) {
#if defined(SHADING_RATIO)
    if (cos_r < kClipCosRadius) return diffuse_part + specular_part;
    return diffuse_part + specular_part * lobe_part_above(dot(s.normal, s.mirror), cos_theta, cos_r, u_shininess);
#else
    return under_tangent_plane(cos_theta) ? diffuse_part : diffuse_part + specular_part;
#endif
}

#if defined(METALLIC_ROUGHNESS)
// glTF's specular lobes at a cell (docs/DESIGN.md §11, "The cells"), both widened by the cell's cap (alpha^2 plus
// r^2 / 8, the cap's spread of the half vector; r^2 = 2 (1 - cos r) for small caps), and cut off beyond
// tan theta_h = 6 alpha about r, which leaves out 1 / 37 of GGX's projected area.
const float kLobeCutoffSquared = 36.0;

float widened_alpha2(float alpha2, float cos_r) {
    return alpha2 + (1.0 - cos_r) / 4.0;
}

// Whether w (t = r.w) lies beyond the cut-off: tan^2 theta_h = (1 - t) / (1 + t) of the lobe about r.
bool beyond_lobe(float t, float widened2) {
    return 1.0 - t > kLobeCutoffSquared * widened2 * (1.0 + t);
}

// The BRDF's specular lobe, f cos theta at w (cos_theta = n.w): F D V n.l.
vec3 brdf_lobe(Surface s, vec3 w, float cos_theta, float widened2) {
    if (cos_theta <= 0.0) return vec3(0.0);
    vec3 h = normalize(s.view + w);
    float m = 1.0 - max(dot(s.view, h), 0.0), m2 = m * m;
    vec3 fresnel = s.gltf.f0 + (1.0 - s.gltf.f0) * (m2 * m2 * m);
    return fresnel * (ggx_distribution(max(dot(s.normal, h), 0.0), widened2) *
                      smith_visibility(cos_theta, max(s.gltf.n_dot_v, 1e-4), s.gltf.alpha2) * cos_theta);
}

// The split sum's specular lobe at w: specular_albedo K(r.w) / integral K, whose sum over the map is
// specular_albedo P(r, alpha).
vec3 split_sum_lobe(Surface s, float t, float widened2) {
    return s.gltf.specular_albedo * reflection_lobe(t, widened2);
}

// A cell's weight for glTF's BRDF, the same in both sums: the fraction is the BRDF's own, its diffuse
// lobe (1 - metallic)(1 - 0.04) baseColor diffuse(n.v) / pi times the cosine's average and its specular lobe.
Reflectivity gltf_reflectivity(Surface s, vec3 w, float cos_r, float cos_theta) {
    vec3 a = s.gltf.diffuse_albedo * (diffuse_average(cos_theta, cos_r) / PI);
    float widened2 = widened_alpha2(s.gltf.alpha2, cos_r);
    if (!beyond_lobe(dot(s.mirror, w), widened2)) a += brdf_lobe(s, w, cos_theta, widened2);
    return Reflectivity(a, a);
}

// FramePlan::compact_lights (render/lights.h): cells much brighter than the map's mean, a sun.
layout(location = LOC_COMPACT_LIGHT_COUNT) uniform int u_compact_light_count;
layout(location = LOC_COMPACT_LIGHTS) uniform ivec4 u_compact_lights;

// The width the split sum's lookup gave a lobe of widened2: the levels about the roughness, or the map and the
// sharpest level widened by the pixel's footprint up to that level's (ggx_lobe_mean, mirror_level_weight).
float split_sum_alpha2(Surface s, float widened2) {
    return widened2 + (below_levels(s.gltf) ? min(0.075 * s.gltf.mirror_spread, kSharpestAlpha * kSharpestAlpha) : 0.0);
}

// The compact lights' reflection both ways, summed over them: L~_i times the BRDF's lobe (`brdf`) and times the
// split sum's (`split_sum`), which the split sum's lookup holds and the BRDF's replaces. The split sum's lobe is
// round about r; the BRDF's, seen off the normal, is narrower and higher (by about 1 / n.v at its peak), so a
// sun's highlight needs its true shape; over a smooth map the split sum is close and the rest of the cells are
// left to it. The BRDF's lobe is widened by the pixel's footprint, the variance of a pixel-wide box in the half
// vector, (|dn/dx|^2 + |dn/dy|^2) / 12 = mirror_spread / 48: a glint smaller than the pixel is its mean over the
// pixel, not its value at the sample.
void compact_light_lobes(Surface s, out vec3 brdf, out vec3 split_sum) {
    brdf = vec3(0.0);
    split_sum = vec3(0.0);
    for (int k = 0; k < u_compact_light_count; ++k) {
        int i = u_compact_lights[k];
        vec3 w = lights[i].direction.xyz;
        float widened2 = widened_alpha2(s.gltf.alpha2, lights[i].direction.w);
        float brdf2 = widened2 + s.gltf.mirror_spread / 48.0;
        float t = dot(s.mirror, w);
        if (beyond_lobe(t, brdf2)) continue;
        brdf += lights[i].radiance.rgb * brdf_lobe(s, w, dot(s.normal, w), brdf2);
        split_sum += lights[i].radiance.rgb * split_sum_lobe(s, t, split_sum_alpha2(s, widened2));
    }
}
#endif

// a(dw_i, w) of cell i, whose direction w_i and cap R = cos r_i come from its light record.
Reflectivity reflectivity(Surface s, int i) {
    vec3 w = lights[i].direction.xyz;
    float cos_r = lights[i].direction.w;
    float cos_theta = dot(s.normal, w);
#if defined(METALLIC_ROUGHNESS) && defined(SHADING_RATIO)
    return gltf_reflectivity(s, w, cos_r, cos_theta);
#else
    float specular = u_k_s > 0.0 && specular_needed(cos_theta) ? specular_average(dot(w, s.mirror), cos_r) : 0.0;
    vec3 diffuse_part = s.k_d * diffuse_average(cos_theta, cos_r);
    float specular_part = u_k_s * specular;
    return Reflectivity(clipped_reflectivity(diffuse_part, specular_part, s, cos_theta, cos_r),
                        diffuse_part + specular_part);
#endif
}
