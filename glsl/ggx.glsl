// glTF's GGX lobe (docs/DESIGN.md §11), the GLSL twin of engine/env/gltf_brdf.h's ggx_distribution and
// smith_visibility (here in alpha^2; tests/brdf/ggx_glsl_test.cpp holds them to the C++).
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
