#pragma once
// Independent numerical integration over spherical caps, for checking engine/env/brdf.cpp (and for the
// figures of Barsi et al. §2.3). Nothing here shares code or formulas with the code under test.
#include <algorithm>
#include <cmath>
#include <numbers>

namespace envshadow::testing {

// Average over a cap of cosine radius `cos_r` of g(cos gamma), gamma being the angle from an axis A that
// makes angle delta (cos delta = `cos_delta`) with the cap's centre. Rings about A: the ring at angle
// gamma has length 2 pi sin gamma, of which the part with w.centre >= cos_r (half-angle Phi(gamma)) lies
// in the cap; dw = sin gamma dgamma dphi. Composite midpoint rule in gamma over the rings that meet the cap.
template <class G>
double cap_average_by_rings(G&& g, double cos_delta, double cos_r, int steps = 200000) {
    constexpr double pi = std::numbers::pi;
    const double delta = std::acos(std::clamp(cos_delta, -1.0, 1.0));
    const double radius = std::acos(std::clamp(cos_r, -1.0, 1.0));
    const double lo = std::max(0.0, delta - radius), hi = std::min(pi, delta + radius);
    const double h = (hi - lo) / steps;
    const double sin_delta = std::sin(delta);
    // The cap's solid angle comes from the same rings, so that the quadrature errors largely cancel.
    double sum = 0.0, area = 0.0;
    for (int k = 0; k < steps; ++k) {
        const double gamma = lo + (k + 0.5) * h;
        const double cg = std::cos(gamma), sg = std::sin(gamma);
        double half_angle;  // of the ring's arc inside the cap
        if (sin_delta * sg < 1e-300) {
            half_angle = cg * cos_delta >= cos_r ? pi : 0.0;
        } else {
            half_angle = std::acos(std::clamp((cos_r - cg * cos_delta) / (sg * sin_delta), -1.0, 1.0));
        }
        sum += g(cg) * 2.0 * half_angle * sg;
        area += 2.0 * half_angle * sg;
    }
    return sum / area;
}

// Brute force over the cap itself: (psi, phi) about the centre, dw = sin psi dpsi dphi, midpoint in both;
// g takes the direction's cosine with an axis at angle delta from the centre. Slow; checks the rings.
template <class G>
double cap_average_brute_force(G&& g, double cos_delta, double cos_r, int steps_psi, int steps_phi) {
    constexpr double pi = std::numbers::pi;
    const double radius = std::acos(std::clamp(cos_r, -1.0, 1.0));
    const double sin_delta = std::sqrt(std::max(0.0, 1.0 - cos_delta * cos_delta));
    double sum = 0.0, area = 0.0;
    for (int i = 0; i < steps_psi; ++i) {
        const double psi = (i + 0.5) * radius / steps_psi;
        const double cp = std::cos(psi), sp = std::sin(psi);
        for (int j = 0; j < steps_phi; ++j) {
            const double phi = (j + 0.5) * 2.0 * pi / steps_phi;
            // centre = z; axis = (sin delta, 0, cos delta); direction = (sp cos phi, sp sin phi, cp).
            const double cos_to_axis = sin_delta * sp * std::cos(phi) + cos_delta * cp;
            sum += g(cos_to_axis) * sp;
            area += sp;
        }
    }
    return sum / area;
}

}  // namespace envshadow::testing
