#pragma once
// GGX written independently of engine/env/gltf_brdf.cpp (Walter et al. 2007's forms, in tan theta; Heitz 2014's
// Lambda for the height-correlated G2), and deterministic quadratures over half vectors and directions, for the
// tests of the glTF BRDF, its DFG table and its prefiltering.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace envshadow::testing {

inline constexpr double kGgxPi = std::numbers::pi;

inline double walter_ggx_distribution(double cos_h, double alpha) {
    if (cos_h <= 0.0) return 0.0;
    const double c2 = cos_h * cos_h, tan2 = (1.0 - c2) / c2;
    const double x = 1.0 + tan2 / (alpha * alpha);
    return 1.0 / (kGgxPi * alpha * alpha * c2 * c2 * x * x);
}

inline double smith_lambda(double cos_x, double alpha) {
    const double c2 = cos_x * cos_x, tan2 = (1.0 - c2) / c2;
    return 0.5 * (std::sqrt(1.0 + alpha * alpha * tan2) - 1.0);
}

inline double height_correlated_g2(double cos_l, double cos_v, double alpha) {
    return 1.0 / (1.0 + smith_lambda(cos_l, alpha) + smith_lambda(cos_v, alpha));
}

// E[g(h)] for h distributed as D(h) (n.h) about n = +Z, i.e. integral of g D (n.h) dh over the hemisphere: the
// midpoints of a steps x steps grid in (xi, phi), with GGX's inverse distribution tan^2 theta = alpha^2 xi / (1 - xi).
template <class G>
double mean_over_ggx_half_vectors(double alpha, int steps, G g) {
    // xi = 1 - (1 - w)^2, midpoints in w weighted by 2 (1 - w): denser towards xi = 1, the grazing half vectors.
    double sum = 0.0;
    for (int a = 0; a < steps; ++a) {
        const double w = (a + 0.5) / steps, xi = 1.0 - (1.0 - w) * (1.0 - w), weight = 2.0 * (1.0 - w);
        const double tan_theta = alpha * std::sqrt(xi / (1.0 - xi));
        const double cos_theta = 1.0 / std::sqrt(1.0 + tan_theta * tan_theta), sin_theta = tan_theta * cos_theta;
        for (int b = 0; b < steps; ++b) {
            const double phi = 2.0 * kGgxPi * (b + 0.5) / steps;
            sum += weight * g(glm::dvec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta));
        }
    }
    return sum / (double(steps) * steps);
}

// integral of g(l) dl over the upper hemisphere (n = +Z): midpoints in theta and phi, weight sin theta.
template <class G>
double integral_over_hemisphere(int steps, G g) {
    double sum = 0.0;
    const double d_theta = 0.5 * kGgxPi / steps, d_phi = 2.0 * kGgxPi / (2 * steps);
    for (int a = 0; a < steps; ++a) {
        const double theta = (a + 0.5) * d_theta;
        for (int b = 0; b < 2 * steps; ++b) {
            const double phi = (b + 0.5) * d_phi;
            sum += g(glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta))) *
                   std::sin(theta);
        }
    }
    return sum * d_theta * d_phi;
}

// The view direction at cos theta_v = n_dot_v in the xz-plane, n = +Z.
inline glm::dvec3 view_at(double n_dot_v) {
    return {std::sqrt(std::max(0.0, 1.0 - n_dot_v * n_dot_v)), 0.0, n_dot_v};
}

// The mirror of v about h.
inline glm::dvec3 reflected(const glm::dvec3& v, const glm::dvec3& h) {
    return 2.0 * glm::dot(v, h) * h - v;
}

}  // namespace envshadow::testing
