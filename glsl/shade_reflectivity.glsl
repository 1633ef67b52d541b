// a(dw_i, w) = k_d a_d + k_s a_s of each cell at the shaded surface (Barsi et al. §2.3, docs/DESIGN.md §4):
//   DIFFUSE_CAP      a_d: the clamped cosine averaged over the cell's cap instead of the centre sample
//   SPECULAR_SINGLE  a_s: the single sample cos^n psi_c instead of the blended average
//   DIFFUSE_ONLY     for materials with k_s = 0: the specular code left out (a uniform branch on u_k_s
//                    still costs its whole body on SIMD CPU rasterisers such as llvmpipe)
//   SHADING_RATIO    the ratio estimator's clipping at the tangent plane (docs/DESIGN.md §4.1)
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

// a(dw_i, w) of cell i, whose direction w_i and cap R = cos r_i come from its light record.
Reflectivity reflectivity(Surface s, int i) {
    vec3 w = lights[i].direction.xyz;
    float cos_r = lights[i].direction.w;
    float cos_theta = dot(s.normal, w);
    float specular = u_k_s > 0.0 && specular_needed(cos_theta) ? specular_average(dot(w, s.mirror), cos_r) : 0.0;
    vec3 diffuse_part = s.k_d * diffuse_average(cos_theta, cos_r);
    float specular_part = u_k_s * specular;
    return Reflectivity(clipped_reflectivity(diffuse_part, specular_part, s, cos_theta, cos_r),
                        diffuse_part + specular_part);
}
