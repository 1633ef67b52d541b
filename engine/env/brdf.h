#pragma once
// The paper's modified Phong BRDF and its averages over a cell (docs/DESIGN.md §2, §4). The C++ twin of
// glsl/brdf.glsl: tests check it against numerical integration, and a GL test keeps the GLSL equal.
//   f_r cos theta' = k_d cos theta' + k_s cos^n psi,   k_d = rho_d / pi,  k_s = rho_s (n + 2) / (2 pi)
namespace envshadow::brdf {

float diffuse_coefficient(float rho_d);                    // k_d
float specular_coefficient(float rho_s, float shininess);  // k_s

// Average of cos^n psi over a cap of cosine radius `cos_r` whose centre is at cos psi_c = `cos_psi_c`
// from the mirror direction: Barsi et al.'s blended formula (exact cap average at psi_c = 0, the
// single sample c^n from psi_c = r on). Multiply by k_s.
float average_specular_blended(float cos_psi_c, float cos_r, float shininess);
// The single sample: max(0, c)^n.
float average_specular_single(float cos_psi_c, float shininess);
// Average of max(0, cos theta) over a cap of cosine radius `cos_r` whose centre makes cos theta_c
// with the normal (exact, also for caps straddling the horizon). Multiply by k_d.
float average_clamped_cosine(float cos_theta_c, float cos_r);

}  // namespace envshadow::brdf
