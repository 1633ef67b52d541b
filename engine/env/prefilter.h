#pragma once
// The environment map convolved with the paper's BRDF lobes, for the ratio estimator (docs/DESIGN.md §4.1):
//   E(n)   = integral of L_env max(0, n . w) dw         (the clamped cosine about the normal)
//   S_n(r) = integral of L_env max(0, r . w)^n dw       (the Phong lobe about the mirror direction)
// over the visible directions (with a ground, the texels below the horizon count as zero, as in the
// decomposition). Computed once per map through spherical harmonics: the map's coefficients up to the
// band the sharpest lobe needs, times the lobes' Funk-Hecke factors, synthesised on one lat-long grid per
// shininess level. Each level stores the normalised lobe S_n (n + 1) / (2 pi), which is smooth in n (the
// map's mean radiance in the lobe: 1 under builtin:constant), so interpolating it in log n between
// levels is accurate; E = pi * level 0 (n = 1).
#include <vector>

#include <glm/vec3.hpp>

#include "env/environment.h"
#include "env/importance.h"
#include "env/level_storage.h"

namespace envshadow {

inline constexpr float kPrefilterMinShininess = 1.0f;
inline constexpr float kPrefilterMaxShininess = 10000.0f;  // shininess outside is clamped to this range

struct PrefilteredLevel {
    float shininess = 1.0f;
    // Lat-long, W = 2H, columns as in the map (phi = 2 pi (i + 0.5) / W) but rows from pole to pole,
    // theta = pi j / (H - 1): a lookup near a pole interpolates towards the pole's own value instead of
    // clamping to a row half a texel away (2% off at the zenith of a 64 x 32 grid, the ground's normal).
    // In texture coordinates: v' = (v (H - 1) + 0.5) / H, v = theta / pi (glsl/shade_ratio.glsl).
    int width = 0, height = 0;
    std::vector<glm::vec3, LevelAllocator<glm::vec3>> texels;  // S_n (n + 1) / (2 pi), texel (i, j) at j * width + i
};

// The two levels a shininess falls between and the weight of the upper one (linear in log n).
struct LevelPair {
    int lower = 0, upper = 0;
    float weight = 0.0f;
};

struct PrefilteredEnvironment {
    std::vector<PrefilteredLevel> levels;  // shininess 10^(k/8) to 1000, then 10^(k/4) to 10^4; levels[0]: n = 1
    double seconds = 0.0;                  // wall time of prefilter_environment

    LevelPair level_pair(float shininess) const;
    // Bilinear lookup of one level, as GL_LINEAR with GL_REPEAT in u and GL_CLAMP_TO_EDGE in v does.
    glm::vec3 sample(int level, const glm::dvec3& direction) const;
    // E(n) about the unit normal `n` and S_n(r) about the unit direction `r`, in map space.
    glm::vec3 irradiance(const glm::dvec3& n) const;
    glm::vec3 specular(const glm::dvec3& r, float shininess) const;
};

// Parallel (TBB). `hemisphere` upper: the directions below the horizon contribute nothing.
PrefilteredEnvironment prefilter_environment(const EnvironmentMap& map, Hemisphere hemisphere);

// 2 pi times the integral of max(0, t)^n P_l(t) dt over [-1, 1] (Funk-Hecke factor of the lobe; P_l the
// Legendre polynomial): the lobe's convolution multiplies degree l of a map's harmonics by it.
double phong_lobe_factor(int l, double shininess);

}  // namespace envshadow
