#pragma once
// The environment convolved with lobes symmetric about an axis, K(r . w), through spherical harmonics
// (docs/DESIGN.md §4.1): the engine under the Phong prefiltering (env/prefilter.h) and the GGX one
// (env/ggx_prefilter.h); internal to the env layer.
#include <vector>

#include <glm/vec3.hpp>

#include "env/environment.h"
#include "env/importance.h"
#include "env/level_storage.h"

namespace envshadow::prefiltering {

inline constexpr int kMaxGridWidth = 1024;  // levels and the source are at most 1024 x 512

struct LobePlan {
    int width = 0;                // of the level's grid, a power of two <= kMaxGridWidth; height width / 2
    int band = 0;                 // the highest degree kept (lowered to the source's and the grid's band)
    std::vector<double> factors;  // factors[l], l = 0..band: the lobe's Funk-Hecke factor times a normalisation
};

// One level: lat-long, W = 2H, columns as in the map, rows from pole to pole (PrefilteredLevel's layout).
struct LobeGrid {
    int width = 0, height = 0;
    std::vector<glm::vec3, LevelAllocator<glm::vec3>> texels;  // texel (i, j) at j * width + i
};

// Level k's texel in direction r: sum_lm factors_l c_lm Y_lm(r), c_lm the exact texel sums of L dw over the
// visible directions (with `hemisphere` upper, those above the horizon); clamped at 0 (a truncated expansion
// rings a little). Levels of one width must be consecutive in `plans`. Parallel (TBB).
std::vector<LobeGrid> convolve_with_lobes(const EnvironmentMap& map, Hemisphere hemisphere,
                                          const std::vector<LobePlan>& plans);

// Bilinear lookup of a grid, as GL_LINEAR with GL_REPEAT in u and GL_CLAMP_TO_EDGE in v does.
glm::vec3 sample_grid(int width, int height, const glm::vec3* texels, const glm::dvec3& direction);

}  // namespace envshadow::prefiltering
