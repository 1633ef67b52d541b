// The C++ twin of glsl/brdf.glsl (docs/DESIGN.md §2, §4; Barsi et al. 2005, §2.3). Computed in double and
// returned as float: this is the side the tests trust, the GLSL is held equal to it.
#include "env/brdf.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace envshadow::brdf {
namespace {

constexpr double kPi = std::numbers::pi;

double clamp_unit(double x) {
    return std::clamp(x, -1.0, 1.0);
}

// Exact average of max(0, cos psi)^n over a cap of cosine radius R centred on the mirror direction
// (Barsi et al., the psi_c = 0 equation): cos psi is uniform over [R, 1] on a cap (dw = dphi dcos psi), so
//   a = (1 - R^{n+1}) / ((n + 1)(1 - R)),   with R^{n+1} read as 0 for R <= 0 (the lobe is clamped).
// 1 - R^{n+1} = -expm1((n + 1) log1p(-(1 - R))) keeps full precision for tiny caps, where 1 - R^{n+1} and
// (n + 1)(1 - R) both vanish (the limit is 1), and cannot overflow for large n. Requires R < 1.
double cap_average_at_centre(double cos_r, double n) {
    const double one_minus_r = 1.0 - cos_r;
    if (cos_r <= 0.0) return 1.0 / ((n + 1.0) * one_minus_r);
    return -std::expm1((n + 1.0) * std::log1p(-one_minus_r)) / ((n + 1.0) * one_minus_r);
}

double single_sample(double cos_psi, double n) {
    return std::pow(std::max(cos_psi, 0.0), n);
}

// atan(z) - z without cancellation for small z (average_clamped_cosine's small caps).
double atan_minus_identity(double z) {
    if (std::abs(z) >= 0.01) return std::atan(z) - z;
    const double z2 = z * z;  // -z^3/3 + z^5/5 - z^7/7 + z^9/9: the next term is below 1e-16 relative
    return -z * z2 * (1.0 / 3.0 - z2 * (1.0 / 5.0 - z2 * (1.0 / 7.0 - z2 / 9.0)));
}

}  // namespace

float diffuse_coefficient(float rho_d) {
    return float(double(rho_d) / kPi);
}

float specular_coefficient(float rho_s, float shininess) {
    return float(double(rho_s) * (double(shininess) + 2.0) / (2.0 * kPi));
}

float average_specular_single(float cos_psi_c, float shininess) {
    return float(single_sample(clamp_unit(cos_psi_c), std::max(double(shininess), 0.0)));
}

// Barsi et al.'s blend of the exact centred cap average and the single sample with weights
// (c - R)/(1 - R) and (1 - c)/(1 - R) (they sum to 1):
//   psi_c >= r:  c^n
//   psi_c <  r:  (1 - R^{n+1})(c - R) / ((n + 1)(1 - R)^2) + c^n (1 - c)/(1 - R)
// Continuous everywhere: at c = R the blend is R^n, the single sample. Inside the cap branch R < c <= 1,
// so 1 - R > 0 (exact in floating point, Sterbenz) and no epsilon is needed: as the cap shrinks both
// terms tend to c^n -> 1 together.
float average_specular_blended(float cos_psi_c, float cos_r, float shininess) {
    const double c = clamp_unit(cos_psi_c), r = clamp_unit(cos_r), n = std::max(double(shininess), 0.0);
    if (c <= r) return float(single_sample(c, n));  // the mirror direction is outside the cap (or on its rim)
    const double one_minus_r = 1.0 - r;
    const double centred = cap_average_at_centre(r, n);
    return float(centred * ((c - r) / one_minus_r) + single_sample(c, n) * ((1.0 - c) / one_minus_r));
}

// Exact average of max(0, cos theta) over a cap of cosine radius R whose centre c makes cos theta_c = t with
// the normal N. Derivation (Stokes on the sphere: for a region A, the vector integral of w dw over A
// equals 1/2 of the boundary integral of w x dw, counter-clockwise seen from outside), so
//   I = integral over A of N.w dw = 1/2 * boundary integral of N.(w x dw),  A = cap cut by the tangent plane.
// Frame: N = z, c = (s, 0, t), s = sin theta_c, rho = sin r = sqrt(1 - R^2). The cap's rim is
//   w(phi) = R c + rho (cos phi e1 + sin phi e2),  e1 = (-t, 0, s) (towards N), e2 = (0, -1, 0),
// (e1, e2, c) right-handed, so N.(w x dw/dphi) = rho^2 t - R rho s cos phi and w.z = R t + rho s cos phi.
//  - the rim above the horizon, |phi| < phi0 with cos phi0 = -R t / (rho s), gives rho^2 t phi0 - R q,
//    q = rho s sin phi0 = sqrt(s^2 - R^2) (half the chord the horizon cuts from the rim's plane);
//  - the horizon (w.z = 0) inside the cap, w.c >= R i.e. |beta| <= beta0 with cos beta0 = R / s, has
//    N.(w x dw) = dbeta there and gives beta0 = acos(R / s) = atan2(q, R).
//   I = rho^2 t phi0 - R q + atan2(q, R),   average = I / (2 pi (1 - R)).
// Fully above the horizon (s <= R: q = 0, phi0 = pi): I = pi (1 - R^2) t, average = t (1 + R)/2, the single
// sample t for a point cap; fully below: phi0 = q = 0, I = 0. Clamping makes these cases, caps larger than
// a hemisphere (R < 0) and s -> 0 fall out of the same formula continuously.
// Small caps on the horizon: I ~ rho^3 while the terms are ~ rho. With z = q / R and rho^2 = 1 - R^2,
//   atan(z) - R q = (atan(z) - z) + rho^2 q / R,   so  I = rho^2 (t phi0 + q / R) + (atan(z) - z),
// whose terms are all ~ rho^3; atan(z) - z comes from its series for small z, and s^2 - R^2 from
// ((1 - R) - t^2 / (1 + s)) (s + R), which does not cancel either.

float average_clamped_cosine(float cos_theta_c, float cos_r) {
    const double t = clamp_unit(cos_theta_c), r = clamp_unit(cos_r);
    const double one_minus_r = 1.0 - r;
    if (one_minus_r <= 0.0) return float(std::max(t, 0.0));  // a point cap: the single sample
    const double rho2 = one_minus_r * (1.0 + r);
    const double s = std::sqrt(std::max(0.0, 1.0 - t * t));
    const double s_minus_r = one_minus_r - t * t / (1.0 + s);
    const double q = std::sqrt(std::max(0.0, s_minus_r * (s + r)));
    // s = 0 or rho = 0: the quotients go to +-inf (never 0/0) and the acos to 0 or pi, as in the limit.
    const double phi0 = std::acos(clamp_unit(-r * t / std::max(std::sqrt(rho2) * s, 1e-300)));
    if (r > 0.5) {
        const double integral = rho2 * (t * phi0 + q / r) + atan_minus_identity(q / r);
        return float(std::max(integral, 0.0) / (2.0 * kPi * one_minus_r));
    }
    const double beta0 = std::acos(clamp_unit(r / std::max(s, 1e-300)));  // = atan2(q, R), also at s = R = 0
    const double integral = rho2 * t * phi0 - r * q + beta0;
    return float(std::max(integral, 0.0) / (2.0 * kPi * one_minus_r));
}

}  // namespace envshadow::brdf
