// glTF's GGX lobe (docs/DESIGN.md §11), the GLSL twin of engine/env/gltf_brdf.h's ggx_distribution and
// smith_visibility (here in alpha^2), and the split sum's round lobe K about the mirror direction
// (tests/brdf/ggx_glsl_test.cpp holds them to the C++ and to quadrature).
#include "constants.glsl"

// GGX's D from cos^2 and sin^2 theta_h: alpha^2 / (pi (cos^2 (alpha^2 - 1) + 1)^2), the bracket summed as
// sin^2 + cos^2 alpha^2 so that a sharp lobe's peak does not cancel in float.
float ggx_distribution_squared(float cos2, float sin2, float alpha2) {
    float d = sin2 + cos2 * alpha2;
    return alpha2 / (PI * d * d);
}

// GGX's D at cos theta_h = c.
float ggx_distribution(float c, float alpha2) {
    float c2 = c * c;
    return ggx_distribution_squared(c2, 1.0 - c2, alpha2);
}

// Smith's height-correlated V = G2 / (4 n.l n.v), for n.l, n.v > 0.
float smith_visibility(float n_dot_l, float n_dot_v, float alpha2) {
    float lambda_v = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - alpha2) + alpha2);
    float lambda_l = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - alpha2) + alpha2);
    return 0.5 / (lambda_v + lambda_l);
}

// The integral over the sphere of the split sum's lobe K(t) = D(sqrt((1 + t) / 2)) max(0, t), t = r.l: in
// closed form 8 a ln(2 a / (1 + a)) / (1 - a)^2 + 4 / (1 - a), a = alpha^2; by its series in e = 1 - a where
// the two terms cancel (4 at alpha = 0, 1 at alpha = 1).
float reflection_lobe_integral(float alpha2) {
    float e = 1.0 - alpha2;
    if (e < 0.1) return 1.0 + e * (2.0 / 3.0 + e * (11.0 / 24.0 + e * (13.0 / 40.0)));
    return 8.0 * alpha2 * log(2.0 * alpha2 / (1.0 + alpha2)) / (e * e) + 4.0 / e;
}

// The split sum's lobe about r normalised, K(t) / its integral: what P(r, alpha) averages the map over
// (cos^2 theta_h = (1 + t) / 2).
float reflection_lobe(float t, float alpha2) {
    if (t <= 0.0) return 0.0;
    return ggx_distribution_squared(0.5 + 0.5 * t, 0.5 - 0.5 * t, alpha2) * t / reflection_lobe_integral(alpha2);
}
