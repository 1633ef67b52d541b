// a(dw_i, w) = k_d a_d + k_s a_s of each cell at the shaded surface (Barsi et al. §2.3, docs/DESIGN.md §4):
//   DIFFUSE_CAP      a_d: the clamped cosine averaged over the cell's cap instead of the centre sample
//   SPECULAR_SINGLE  a_s: the single sample cos^n psi_c instead of the blended average
//   DIFFUSE_ONLY     for materials with k_s = 0: the specular code left out (a uniform branch on u_k_s
//                    still costs its whole body on SIMD CPU rasterisers such as llvmpipe)
//   SHADING_RATIO    the ratio estimator's clipping at the tangent plane (docs/DESIGN.md §4.1)
//   METALLIC_ROUGHNESS (with SHADING_RATIO) glTF's BRDF in place of the paper's, and the map's compact
//                    sources (a sun) with that BRDF's own lobe beside the split sum (docs/DESIGN.md §11)
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

// Schlick's Fresnel F0 + (1 - F0)(1 - v.h)^5.
vec3 schlick_fresnel(vec3 f0, float v_dot_h) {
    float m = 1.0 - max(v_dot_h, 0.0), m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// The BRDF's specular lobe, f cos theta at w for the view v: F D V n.l, with D at the normal n and V and the
// cosine at the n.v and n.l given (cos_theta; those of n itself, but for brdf_lobe_over_footprint).
vec3 brdf_lobe(Surface s, vec3 n, vec3 v, float n_dot_v, vec3 w, float cos_theta, float widened2) {
    if (cos_theta <= 0.0) return vec3(0.0);
    vec3 h = normalize(v + w);
    float d_v = ggx_distribution(max(dot(n, h), 0.0), widened2) *
                smith_visibility(cos_theta, max(n_dot_v, 1e-4), s.gltf.alpha2);
    return schlick_fresnel(s.gltf.f0, dot(v, h)) * (d_v * cos_theta);
}

// The lobe widened by the pixel's footprint (the normal's turn across it, footprint2 in alpha^2): the glint lies
// where the normal turns to h, so the visibility and the cosine are taken at the normal the glint most likely has,
// n moved towards h by the footprint's share of the widened width (the two spreads' product), D at n itself. At
// n's own n.v they blew up where the footprint reaches over a silhouette (V ~ 1 / (2 alpha n.l) at n.v = 0).
vec3 brdf_lobe_over_footprint(Surface s, vec3 n, vec3 v, vec3 w, float widened2, float footprint2) {
    vec3 at_glint = normalize(mix(n, normalize(v + w), footprint2 / (widened2 + footprint2)));
    float n_dot_v = dot(at_glint, v);
    if (n_dot_v <= 0.0) return vec3(0.0);
    return brdf_lobe(s, n, v, n_dot_v, w, dot(at_glint, w), widened2 + footprint2);
}

vec3 brdf_lobe(Surface s, vec3 w, float cos_theta, float widened2) {
    return brdf_lobe(s, s.normal, s.view, s.gltf.n_dot_v, w, cos_theta, widened2);
}

// A cell's weight for glTF's BRDF, the same in both sums: the fraction is the BRDF's own, its diffuse
// lobe (1 - metallic)(1 - 0.04) baseColor diffuse(n.v) / pi times the cosine's average and its specular lobe.
Reflectivity gltf_reflectivity(Surface s, vec3 w, float cos_r, float cos_theta) {
    vec3 a = s.gltf.diffuse_albedo * (diffuse_average(cos_theta, cos_r) / PI);
    float widened2 = widened_alpha2(s.gltf.alpha2, cos_r);
    if (!beyond_lobe(dot(s.mirror, w), widened2)) a += brdf_lobe(s, w, cos_theta, widened2);
    return Reflectivity(a, a);
}

// The map's compact sources (env/compact_sources.h), which the split sum's levels and mirror leave out: world
// direction and cos r of each one's cap, and its integral of L dw.
layout(location = LOC_COMPACT_LIGHT_COUNT) uniform int u_compact_light_count;
layout(location = LOC_COMPACT_DIRECTIONS) uniform vec4 u_compact_directions[MAX_COMPACT_SOURCES];
layout(location = LOC_COMPACT_RADIANCES) uniform vec4 u_compact_radiances[MAX_COMPACT_SOURCES];

// Where the pixel's footprint is wider than this many times a source's lobe, the lobe is averaged over a grid
// of sub-pixels rather than widened as a whole: a glint smaller than the pixel then lands in the sub-pixels
// where the box-filtered reference has it, not in a round blur about the pixel's centre. Only within
// kGridReach widths of the widened lobe (tan theta_h; GGX is 1% of its peak at 3): beyond, its tail is smooth.
const float kFootprintOverLobe = 0.05;
const int kFootprintGrid = 8;
const float kGridReach = 3.0;

// The BRDF's lobe at w averaged over the part of the pixel the fragment covers: the normal n + dn/dx x + dn/dy y
// and the view likewise at the centres of a kFootprintGrid^2 grid over the pixel, those in the covered quarters
// (pixel_footprint.glsl), the lobe widened by its sub-pixel's share of the footprint (twice the peak-matched width,
// which leaves the sum of the sub-pixels' lobes smooth).
vec3 brdf_lobe_over_pixel(Surface s, vec3 w, float widened2, float footprint2) {
    const float cell = 1.0 / float(kFootprintGrid);
    float sub_pixel2 = widened2 + 2.0 * footprint2 * (cell * cell);
    vec3 sum = vec3(0.0);
    float sub_pixels = 0.0;
    for (int j = 0; j < kFootprintGrid; ++j) {
        for (int i = 0; i < kFootprintGrid; ++i) {
            vec2 offset = (vec2(i, j) + 0.5) * cell - 0.5;
            if (!covers(s.pixel, offset)) continue;
            vec3 n = normal_at(s.pixel, offset);
            vec3 v = view_at(s.pixel, offset);
            float n_dot_v = dot(n, v);
            if (n_dot_v <= 0.0) continue;  // carried past the silhouette: not on the surface
            sum += brdf_lobe_over_footprint(s, n, v, w, widened2, sub_pixel2 - widened2);
            sub_pixels += 1.0;
        }
    }
    return sub_pixels > 0.0 ? sum / sub_pixels : vec3(0.0);
}

// The compact sources' reflection, summed over them: L~ times the BRDF's lobe, widened by the source's cap and
// the pixel's footprint to the peak of their convolution (a disc of radius a about a lobe alpha peaks at
// 1 / (pi (alpha^2 + a^2)): the cap's half-vector radius^2 (1 - cos r) / 2, the footprint's a_x a_y / pi in
// the normal against the half vector). The split sum's lobe is round about r; the BRDF's, seen off the normal,
// is narrower and higher (by about 1 / n.v at its peak), so a sun's highlight needs its true shape. Where the
// footprint is wide against the lobe the lobe is averaged over the pixel instead (brdf_lobe_over_pixel): a
// glint smaller than the pixel is its mean over the pixel, not its value at the sample. The whole lobe, without
// the cells' cut-off (beyond_lobe): a sun's tail beyond it holds 1/37 of its light.
vec3 compact_source_lobes(Surface s) {
    // At the pixel's centre, the same for every sample of the pixel the shader runs for; at the sample where the
    // centre lies past the silhouette (the normal carried there faces away).
    bool centre_on_surface = dot(s.pixel.normal, s.pixel.view) > 0.0;
    vec3 n = centre_on_surface ? s.pixel.normal : s.normal, v = centre_on_surface ? s.pixel.view : s.view;
    vec3 r = reflect(-v, n);
    vec3 brdf = vec3(0.0);
    for (int k = 0; k < u_compact_light_count; ++k) {
        vec3 w = u_compact_directions[k].xyz;
        // The normal's change across the pixel against the half vector's (dh = (I - h h^T) dv / |v + w|).
        vec3 h = normalize(v + w);
        float to_h = 1.0 / length(v + w);
        vec3 dm_dx = s.pixel.normal_dx - (s.pixel.view_dx - h * dot(h, s.pixel.view_dx)) * to_h;
        vec3 dm_dy = s.pixel.normal_dy - (s.pixel.view_dy - h * dot(h, s.pixel.view_dy)) * to_h;
        float footprint2 = (dot(dm_dx, dm_dx) + dot(dm_dy, dm_dy)) / (2.0 * PI);
        float widened2 = s.gltf.alpha2 + (1.0 - u_compact_directions[k].w) / 2.0;
        float t = dot(r, w);
        bool in_grid_reach = 1.0 - t <= kGridReach * kGridReach * (widened2 + footprint2) * (1.0 + t);
        vec3 lobe;
        if (footprint2 <= kFootprintOverLobe * widened2)
            lobe = brdf_lobe_over_footprint(s, n, v, w, widened2, footprint2);
        else if (in_grid_reach)
            lobe = brdf_lobe_over_pixel(s, w, widened2, footprint2);
        else  // the tail, smooth over the pixel: its value at the centre, not widened (which raises the tail)
            lobe = brdf_lobe_over_footprint(s, n, v, w, widened2, 0.0);
        brdf += u_compact_radiances[k].rgb * lobe;
    }
    return brdf;
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
