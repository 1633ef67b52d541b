// Average reflectivity of the paper's modified Phong BRDF over a cell (Barsi et al. §2.3,
// DESIGN.md §4). The C++ twin is engine/env/brdf.cpp; a GL test keeps the two equal. Multiply the
// specular averages by k_s = rho_s (n + 2) / (2 pi) and the cosine average by k_d = rho_d / pi.
#include "constants.glsl"

// The single sample a_s / k_s = cos^n psi_c (the paper's Fig. 7, left): over-bright where a small
// lobe meets a large cell.
float average_specular_single(float cos_psi_c, float n) {
    return pow(max(cos_psi_c, 0.0), n);
}

// Exact average of max(0, cos psi)^n over a cap of cosine radius R centred on the mirror
// direction: (1 - R^{n+1}) / ((n + 1)(1 - R)) (the paper's psi_c = 0 case; R^{n+1} becomes
// max(R, 0)^{n+1} for caps wider than a hemisphere). Series where 1 - R^{n+1} would cancel.
float cap_average_specular(float cos_r, float n) {
    float t = 1.0 - cos_r;  // exact in float for cos_r in [0.5, 1]
    float m = n + 1.0;
    if (m * t < 1e-3)  // (1 - (1 - t)^m) / (m t) = 1 - (m - 1) t / 2 + (m - 1)(m - 2) t^2 / 6 - ...
        return 1.0 - 0.5 * (m - 1.0) * t + (m - 1.0) * (m - 2.0) * t * t / 6.0;
    return (1.0 - pow(max(cos_r, 0.0), m)) / (m * t);
}

// Barsi et al.'s blended average: the exact cap average at psi_c = 0 blended towards the single
// sample c^n with weight (1 - c) / (1 - R), reaching it at psi_c = r_i; the single sample beyond:
//   a_s / k_s = (1 - R^{n+1})(c - R) / ((n + 1)(1 - R)^2) + c^n (1 - c) / (1 - R).
float average_specular_blended(float cos_psi_c, float cos_r, float n) {
    float c = clamp(cos_psi_c, -1.0, 1.0);
    if (c <= cos_r) return average_specular_single(c, n);  // psi_c >= r_i (also every c when R = 1)
    float w = (1.0 - c) / (1.0 - cos_r);                     // c > R, so 1 - R > 0
    return cap_average_specular(cos_r, n) * (1.0 - w) + pow(c, n) * w;
}

// Integral of max(0, cos theta) over a cap of half-angle sigma (sin^2 sigma = s2, sigma <= pi/2)
// whose centre makes cos theta_c with the normal. Exact: pi s2 cos theta_c while the cap is above
// the horizon; Snyder's form factor of a spherical cap where it straddles it.
float cap_integral_clamped_cosine(float cos_theta_c, float cos_r) {
    float s2 = max(1.0 - cos_r * cos_r, 0.0);
    if (cos_theta_c * cos_theta_c >= s2) return PI * s2 * max(cos_theta_c, 0.0);
    float sin_theta_c = sqrt(max(1.0 - cos_theta_c * cos_theta_c, 0.0));
    if (s2 < 1e-4) {
        // Tiny cap (sigma < 0.01): the terms below cancel to O(sigma^3) in float; treat the cap as a
        // flat disc on which cos theta = cos theta_c + a x (a = sin sigma sin theta_c, |x| <= 1),
        // whose clamped average is exact to O(sigma^2).
        float a = sqrt(s2) * sin_theta_c;
        float d = clamp(cos_theta_c / a, -1.0, 1.0), e = sqrt(1.0 - d * d);
        float average = a / PI * (d * (0.5 * PI + d * e + asin(d)) + 2.0 / 3.0 * e * e * e);
        return average * 2.0 * PI * (1.0 - cos_r);
    }
    float x = cos_r / sqrt(s2);  // cot sigma
    float y = clamp(-x * cos_theta_c / sin_theta_c, -1.0, 1.0);
    float sin_theta_sqrt_y = sin_theta_c * sqrt(1.0 - y * y);
    return (cos_theta_c * acos(y) - x * sin_theta_sqrt_y) * s2 + atan(sin_theta_sqrt_y, x);
}

// Average of max(0, cos theta) over the cell's cap: exact also for caps straddling the horizon
// (the "cap" diffuse mode; the paper's centre sample is max(0, cos theta_c)). Caps wider than a
// hemisphere are the whole sphere (integral pi) minus the opposite cap.
float average_clamped_cosine(float cos_theta_c, float cos_r) {
    float t = 1.0 - cos_r;
    if (t < 1e-6) return max(cos_theta_c, 0.0);  // a point: the centre sample
    float integral = cos_r >= 0.0 ? cap_integral_clamped_cosine(cos_theta_c, cos_r)
                                  : PI - cap_integral_clamped_cosine(-cos_theta_c, -cos_r);
    return max(integral, 0.0) / (2.0 * PI * t);
}
