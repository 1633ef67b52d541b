#pragma once
// The split sum's first factor (docs/DESIGN.md §11): the environment averaged over the GGX lobe of the glTF
// BRDF (env/gltf_brdf.h) about the mirror direction r, with the usual approximation n = v = r (Karis 2013):
//   P(r, alpha) = integral of L_env(l) K(r . l) dl / integral of K(r . l) dl over the sphere,
//   K(t) = D(sqrt((1 + t) / 2)) max(0, t)
// (D at the half vector of r and l, weighted by n.l as Karis's and Filament's prefilters do), over the visible
// directions (with a ground, the texels below the horizon count as zero, as in §4.1). 1 under a constant map.
// K is symmetric about r, so the map is convolved through spherical harmonics (env/lobe_convolution.h) with
// K's Funk-Hecke factors, computed by quadrature: exact up to the truncation of the expansion.
#include <vector>

#include <glm/vec3.hpp>

#include "env/environment.h"
#include "env/importance.h"
#include "env/level_storage.h"
#include "env/prefilter.h"

namespace envshadow {

// The sharpest level: its lobe (alpha = 1/64, about 0.02 rad wide) still fits the band of a 1024-wide source.
// Roughness below it is looked up at it: blending towards the map itself (roughness 0) is the renderer's.
inline constexpr float kGgxPrefilterMinRoughness = 0.125f;
inline constexpr int kGgxPrefilterLevels = 16;  // roughness 0.125 * 2^(k / 5): alpha 2^(2/5) = 1.32x apart

struct GgxPrefilteredLevel {
    float roughness = 1.0f;
    // As PrefilteredLevel: lat-long, W = 2H, rows from pole to pole, texel (i, j) at j * width + i.
    int width = 0, height = 0;
    std::vector<glm::vec3, LevelAllocator<glm::vec3>> texels;  // P(r, alpha)
};

struct GgxPrefilteredEnvironment {
    std::vector<GgxPrefilteredLevel> levels;   // roughness increasing, levels[0] at kGgxPrefilterMinRoughness
    Hemisphere hemisphere = Hemisphere::full;  // the directions it integrates over
    double seconds = 0.0;                      // wall time of prefilter_environment_ggx

    // The two levels about roughness (clamped to [kGgxPrefilterMinRoughness, 1]) and the upper one's weight,
    // linear in log roughness.
    LevelPair level_pair(float roughness) const;
    // Bilinear lookup of one level (as GL_LINEAR, GL_REPEAT in u, GL_CLAMP_TO_EDGE in v).
    glm::vec3 sample(int level, const glm::dvec3& direction) const;
    // P(r, alpha(roughness)) about the unit direction r in map space, between level_pair's levels.
    glm::vec3 radiance(const glm::dvec3& r, float roughness) const;
};

// Below kGgxPrefilterMinRoughness the lobe is sharper than the sharpest level: the renderer blends that level
// with the map itself (the mirror, roughness 0), linearly in alpha = roughness^2. The weight of the level, in
// [0, 1]; 1 from kGgxPrefilterMinRoughness up.
float ggx_sharpest_level_weight(float roughness);

// Level k's roughness: kGgxPrefilterMinRoughness * 2^(k / 5).
double ggx_prefilter_level_roughness(int k);

// Parallel (TBB). `hemisphere` upper: the directions below the horizon contribute nothing.
GgxPrefilteredEnvironment prefilter_environment_ggx(const EnvironmentMap& map, Hemisphere hemisphere);

// Lambda_l / Lambda_0 for l = 0..band, Lambda_l = 2 pi integral K(t) P_l(t) dt (P_l Legendre): convolving with
// K / Lambda_0 multiplies degree l of a map's harmonics by it.
std::vector<double> ggx_lobe_factors(double alpha, int band);

}  // namespace envshadow
