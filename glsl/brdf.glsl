// Average reflectivity of the paper's modified Phong BRDF over a cell (Barsi et al. §2.3,
// docs/DESIGN.md §4). The C++ twin is engine/env/brdf.cpp; a GL test keeps the two equal. Multiply the
// specular averages by k_s = rho_s (n + 2) / (2 pi) and the cosine average by k_d = rho_d / pi.
#include "constants.glsl"

// ln(1 - x) for x in [0, 1), by its series where log(1 - x) would lose the digits of a small x
// (exact for 1 - x >= 1/2).
float log_one_minus(float x) {
    if (x >= 0.01) return log(1.0 - x);
    return -x * (1.0 + x * (0.5 + x * (1.0 / 3.0 + x * (0.25 + x * 0.2))));  // next term x^6/6 < 2e-13
}

// 1 - e^y for y <= 0, without cancellation for small |y|.
float one_minus_exp(float y) {
    if (y < -0.1) return 1.0 - exp(y);
    return -y * (1.0 + y * (0.5 + y * (1.0 / 6.0 + y * (1.0 / 24.0 + y * (1.0 / 120.0 + y / 720.0)))));
}

// The single sample a_s / k_s = max(0, cos psi_c)^n (the paper's Fig. 7, left): over-bright where a
// small lobe meets a large cell. Sharp lobes (n up to 10^4) live where cos psi is near 1; there
// pow's log2 loses the digits that n multiplies, so c^n = exp(n ln(1 - (1 - c))).
float average_specular_single(float cos_psi_c, float n) {
    float c = clamp(cos_psi_c, 0.0, 1.0);
    return c >= 0.5 ? exp(n * log_one_minus(1.0 - c)) : pow(c, n);
}

// Exact average of max(0, cos psi)^n over a cap of cosine radius R centred on the mirror
// direction: (1 - R^{n+1}) / ((n + 1)(1 - R)) (the paper's psi_c = 0 case; R^{n+1} becomes
// max(R, 0)^{n+1} for caps wider than a hemisphere). 1 - R^{n+1} = 1 - exp((n + 1) ln R) is
// computed without cancellation, so tiny caps need no special case. Requires R < 1.
float cap_average_specular(float cos_r, float n) {
    float t = 1.0 - cos_r;  // exact in float for cos_r in [0.5, 1]
    float m = n + 1.0;
    if (cos_r <= 0.0) return 1.0 / (m * t);
    return one_minus_exp(m * log_one_minus(t)) / (m * t);
}

// Barsi et al.'s blended average: the exact cap average at psi_c = 0 blended towards the single
// sample c^n with weight (1 - c) / (1 - R), reaching it at psi_c = r_i; the single sample beyond:
//   a_s / k_s = (1 - R^{n+1})(c - R) / ((n + 1)(1 - R)^2) + c^n (1 - c) / (1 - R).
float average_specular_blended(float cos_psi_c, float cos_r, float n) {
    float c = clamp(cos_psi_c, -1.0, 1.0);
    if (c <= cos_r) return average_specular_single(c, n);  // psi_c >= r_i (also every c when R = 1)
    float w = (1.0 - c) / (1.0 - cos_r);                     // c > R, so 1 - R > 0
    return cap_average_specular(cos_r, n) * (1.0 - w) + average_specular_single(c, n) * w;  // c < 0 in caps wider than a hemisphere
}

// atan(z) - z, by its series where the difference would cancel in float.
float atan_minus_identity(float z) {
    if (abs(z) >= 0.5) return atan(z) - z;
    // sum over k >= 1 of (-1)^k z^{2k+1} / (2k+1), to k = 12: the rest is under 1e-8 of the sum.
    float z2 = z * z, sum = 0.0;
    for (int k = 12; k >= 1; --k) sum = z2 * ((k % 2 == 0 ? 1.0 : -1.0) / float(2 * k + 1) + sum);
    return z * sum;
}

// acos through atan: llvmpipe's acos is off by ~5e-5, its atan is not.
float precise_acos(float x) {
    x = clamp(x, -1.0, 1.0);
    return atan(sqrt(max((1.0 - x) * (1.0 + x), 0.0)), x);
}

// Average of max(0, cos theta) over the cell's cap whose centre makes cos theta_c = t with the
// normal, exact also for caps straddling the horizon (the "cap" diffuse mode; the paper's centre
// sample is max(0, cos theta_c)). The same closed form as engine/env/brdf.cpp (see the derivation
// there): with R = cos r, rho^2 = 1 - R^2, s = sin theta_c, q = sqrt(s^2 - R^2) (0 when the cap
// is wholly above or below the horizon) and cos phi0 = -R t / (rho s),
//   integral = rho^2 t phi0 - R q + atan2(q, R),
// rearranged for R > 1/2 as rho^2 (t phi0 + q / R) + (atan(q / R) - q / R) so small caps on the
// horizon do not cancel. Caps wider than a hemisphere come out of the same formula.
float average_clamped_cosine(float cos_theta_c, float cos_r) {
    float t = clamp(cos_theta_c, -1.0, 1.0), r = clamp(cos_r, -1.0, 1.0);
    float one_minus_r = 1.0 - r;
    if (one_minus_r <= 0.0) return max(t, 0.0);  // a point cap: the centre sample
    float rho2 = one_minus_r * (1.0 + r);
    float s = sqrt(max(1.0 - t * t, 0.0));
    float s_minus_r = one_minus_r - t * t / (1.0 + s);  // s - R without cancellation
    float q = sqrt(max(s_minus_r * (s + r), 0.0));
    float phi0 = precise_acos(-r * t / max(sqrt(rho2) * s, 1e-30));
    float integral;
    if (r > 0.5) {
        integral = rho2 * (t * phi0 + q / r) + atan_minus_identity(q / r);
    } else {
        float beta0 = atan(q, r);
        integral = rho2 * t * phi0 - r * q + beta0;
    }
    return max(integral, 0.0) / (2.0 * PI * one_minus_r);
}
