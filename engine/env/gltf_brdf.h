#pragma once
// The glTF 2.0 metallic-roughness BRDF (the specification's Appendix B; docs/DESIGN.md §11), in double
// precision for the reference and as the truth of the split-sum tables (env/split_sum.h):
//   f = (1 - metallic) (1 - F_d) baseColor / pi  +  F D V
//   D = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2),  alpha = roughness^2       (GGX / Trowbridge-Reitz)
//   V = G2 / (4 n.l n.v), G2 the height-correlated Smith masking-shadowing of GGX
//   F = F0 + (1 - F0) (1 - v.h)^5 with F0 = mix(0.04, baseColor, metallic); F_d the same with F0 = 0.04
// That is the normative mix(dielectric_brdf, metal_brdf, metallic), dielectric_brdf = fresnel_mix(1.5,
// diffuse, specular) and metal_brdf = conductor_fresnel(baseColor, specular): the diffuse is weighted by the
// dielectric's Fresnel, not by the mixed F (the two differ for 0 < metallic < 1).
#include <glm/vec3.hpp>

namespace envshadow::gltf_brdf {

inline constexpr double kDielectricF0 = 0.04;  // ior 1.5
// GGX is a delta at alpha = 0; below this the distribution's peak overflows a float (the GLSL side).
inline constexpr double kMinAlpha = 1e-3;

struct MetallicRoughness {  // the defaults are glTF's
    glm::dvec3 base_color{1.0};
    double metallic = 1.0;
    double roughness = 1.0;  // perceptual, as in the file
};

// roughness^2 (roughness clamped to [0, 1]), at least kMinAlpha.
double alpha_from_roughness(double roughness);
glm::dvec3 specular_f0(const MetallicRoughness& material);  // mix(0.04, baseColor, metallic)

// GGX normal distribution at cos theta_h = n_dot_h (0 for n_dot_h <= 0). Integrates D (n.h) dh to 1.
double ggx_distribution(double n_dot_h, double alpha);
// Smith's masking of one direction (n_dot_x > 0) for GGX: 2 n.x / (n.x + sqrt(alpha^2 + (1 - alpha^2) n.x^2)).
double smith_masking(double n_dot_x, double alpha);
// Height-correlated Smith visibility V = G2 / (4 n.l n.v) (Heitz 2014), for n_dot_l, n_dot_v > 0.
double smith_visibility(double n_dot_l, double n_dot_v, double alpha);
// Schlick's weight (1 - v.h)^5 and the Fresnel term F0 + (1 - F0) (1 - v.h)^5.
double schlick_weight(double v_dot_h);
glm::dvec3 schlick_fresnel(const glm::dvec3& f0, double v_dot_h);

struct Lobes {
    glm::dvec3 diffuse{0.0};   // (1 - metallic) (1 - F_d) baseColor / pi
    glm::dvec3 specular{0.0};  // F D V
};
// f_r(l, v) (without the cosine) for unit vectors; zero unless n.l > 0 and n.v > 0 (one-sided: the caller
// turns the normal towards the viewer). Reciprocal: evaluate(n, v, l) == evaluate(n, l, v).
Lobes evaluate_lobes(const MetallicRoughness& material, const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& l);
glm::dvec3 evaluate(const MetallicRoughness& material, const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& l);

// Importance sampling of the specular lobe by its visible normals (Heitz 2018, "Sampling the GGX
// Distribution of Visible Normals"): h drawn with density G1(v) max(0, v.h) D(h) / n.v, l the mirror of v
// about h, so l has density pdf = G1(v) D(h) / (4 n.v) over the whole sphere (directions under the surface
// included: their f_r is zero). For n.v > 0; u1, u2 uniform in [0, 1).
struct DirectionSample {
    glm::dvec3 direction{0.0};
    double pdf = 0.0;  // per unit solid angle
};
DirectionSample sample_ggx_reflection(const glm::dvec3& n, const glm::dvec3& v, double alpha, double u1, double u2);
double ggx_reflection_pdf(const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& l, double alpha);

}  // namespace envshadow::gltf_brdf
