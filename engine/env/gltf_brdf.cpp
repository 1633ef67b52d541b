// The glTF 2.0 metallic-roughness BRDF and the sampling of its specular lobe (docs/DESIGN.md §11).
#include "env/gltf_brdf.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace envshadow::gltf_brdf {

namespace {

constexpr double kPi = std::numbers::pi;

// A right-handed orthonormal frame about the unit vector n (Duff et al. 2017, "Building an Orthonormal
// Basis, Revisited").
void tangent_frame(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double c = n.x * n.y * a;
    t = glm::dvec3(1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x);
    b = glm::dvec3(c, sign + n.y * n.y * a, -n.y);
}

}  // namespace

double alpha_from_roughness(double roughness) {
    const double r = std::clamp(roughness, 0.0, 1.0);
    return std::max(r * r, kMinAlpha);
}

glm::dvec3 specular_f0(const MetallicRoughness& material) {
    return glm::dvec3(kDielectricF0) * (1.0 - material.metallic) + material.base_color * material.metallic;
}

double ggx_distribution(double n_dot_h, double alpha) {
    if (n_dot_h <= 0.0) return 0.0;
    const double a2 = alpha * alpha;
    const double d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (kPi * d * d);
}

double smith_masking(double n_dot_x, double alpha) {
    const double a2 = alpha * alpha;
    return 2.0 * n_dot_x / (n_dot_x + std::sqrt(a2 + (1.0 - a2) * n_dot_x * n_dot_x));
}

double smith_visibility(double n_dot_l, double n_dot_v, double alpha) {
    const double a2 = alpha * alpha;
    const double view = n_dot_l * std::sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
    const double light = n_dot_v * std::sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    return 0.5 / (view + light);
}

double schlick_weight(double v_dot_h) {
    const double x = std::clamp(1.0 - v_dot_h, 0.0, 1.0);
    const double x2 = x * x;
    return x2 * x2 * x;
}

glm::dvec3 schlick_fresnel(const glm::dvec3& f0, double v_dot_h) {
    return f0 + (glm::dvec3(1.0) - f0) * schlick_weight(v_dot_h);
}

Lobes evaluate_lobes(const MetallicRoughness& material, const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& l) {
    const double n_dot_l = glm::dot(n, l), n_dot_v = glm::dot(n, v);
    if (n_dot_l <= 0.0 || n_dot_v <= 0.0) return {};
    const glm::dvec3 h = glm::normalize(v + l);
    const double v_dot_h = glm::dot(v, h);
    const double alpha = alpha_from_roughness(material.roughness);
    const double weight = schlick_weight(v_dot_h);
    const double dielectric_fresnel = kDielectricF0 + (1.0 - kDielectricF0) * weight;
    const glm::dvec3 f0 = specular_f0(material);
    Lobes lobes;
    lobes.diffuse = material.base_color * ((1.0 - material.metallic) * (1.0 - dielectric_fresnel) / kPi);
    lobes.specular = (f0 + (glm::dvec3(1.0) - f0) * weight) *
                     (ggx_distribution(glm::dot(n, h), alpha) * smith_visibility(n_dot_l, n_dot_v, alpha));
    return lobes;
}

glm::dvec3 evaluate(const MetallicRoughness& material, const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& l) {
    const Lobes lobes = evaluate_lobes(material, n, v, l);
    return lobes.diffuse + lobes.specular;
}

DirectionSample sample_ggx_reflection(const glm::dvec3& n, const glm::dvec3& v, double alpha, double u1, double u2) {
    glm::dvec3 t, b;
    tangent_frame(n, t, b);
    const glm::dvec3 local_v(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n));
    // Heitz 2018, listing 1 (isotropic): the view direction in the hemisphere configuration (alpha = 1).
    const glm::dvec3 vh = glm::normalize(glm::dvec3(alpha * local_v.x, alpha * local_v.y, local_v.z));
    const double length2 = vh.x * vh.x + vh.y * vh.y;
    const glm::dvec3 t1 = length2 > 0.0 ? glm::dvec3(-vh.y, vh.x, 0.0) / std::sqrt(length2) : glm::dvec3(1.0, 0.0, 0.0);
    const glm::dvec3 t2 = glm::cross(vh, t1);
    const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
    const double p1 = r * std::cos(phi);
    const double s = 0.5 * (1.0 + vh.z);
    const double p2 = (1.0 - s) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) + s * r * std::sin(phi);
    const glm::dvec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2)) * vh;
    const glm::dvec3 local_h = glm::normalize(glm::dvec3(alpha * nh.x, alpha * nh.y, std::max(0.0, nh.z)));
    const glm::dvec3 h = local_h.x * t + local_h.y * b + local_h.z * n;
    DirectionSample sample;
    sample.direction = glm::normalize(2.0 * glm::dot(v, h) * h - v);
    sample.pdf = ggx_reflection_pdf(n, v, sample.direction, alpha);
    return sample;
}

double ggx_reflection_pdf(const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& l, double alpha) {
    const double n_dot_v = glm::dot(n, v);
    const glm::dvec3 sum = v + l;
    const double length = glm::length(sum);
    if (n_dot_v <= 0.0 || length <= 0.0) return 0.0;
    const glm::dvec3 h = sum / length;
    return smith_masking(n_dot_v, alpha) * ggx_distribution(glm::dot(n, h), alpha) / (4.0 * n_dot_v);
}

}  // namespace envshadow::gltf_brdf
