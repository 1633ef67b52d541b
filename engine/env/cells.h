#pragma once
// Directional cells of an environment map (docs/DESIGN.md §3): the output of every decomposition method,
// and what the renderer turns into lights.
#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "env/environment.h"
#include "env/importance.h"
#include "env/nearest_site.h"

namespace envshadow {

struct Cell {
    glm::vec3 direction{0.0f, 1.0f, 0.0f};  // unit vector, map space (rotate by the scene's env rotation)
    glm::vec3 radiance{0.0f};               // L~_i = sum over the cell's texels of L dw (RGB)
    float solid_angle = 0.0f;               // dw_i = sum of texel solid angles
    float cos_radius = 1.0f;                // paper's cap: 1 - dw_i / (2 pi)
    float cos_radius_weighted = 1.0f;       // radiance-weighted cap: 2 (sum I (w.c) / sum I) - 1
};

enum class Method { lloyd, ccvt, mediancut, random, fs };
inline constexpr EnumName<Method> kMethodNames[] = {{Method::lloyd, "lloyd"},
                                                    {Method::ccvt, "ccvt"},
                                                    {Method::mediancut, "mediancut"},
                                                    {Method::random, "random"},
                                                    {Method::fs, "fs"}};
constexpr std::span<const EnumName<Method>> enum_names(Method) {
    return kMethodNames;
}

inline constexpr int kMaxLights = 256;

struct DecomposeOptions {
    Method method = Method::lloyd;
    int lights = 128;        // 1..kMaxLights (mediancut rounds down to a power of two; fs gives N or N - 1)
    std::uint64_t seed = 1;  // random and lloyd draw their initial sites with it (ccvt's start needs none)
    SiteSearch search = SiteSearch::tiles;
    // upper: only the texels above the horizon (docs/DESIGN.md §3.1), for a scene with a ground plane.
    Hemisphere hemisphere = Hemisphere::full;
};

// Decomposition::texel_cell of a texel outside the hemisphere decomposed (below the horizon).
inline constexpr std::uint16_t kNoCell = 0xFFFF;

struct Decomposition {
    Method method = Method::lloyd;
    Hemisphere hemisphere = Hemisphere::full;
    int width = 0, height = 0;
    std::vector<Cell> cells;
    std::vector<std::uint16_t> texel_cell;  // cell index of every texel (j * width + i); kNoCell outside
                                            // the hemisphere (the middle row of an odd map is inside)
    glm::dvec3 integral{0.0};               // integral of L dw over the hemisphere, directly from the map
    double seconds = 0.0;
    int iterations = 0;               // Lloyd / CCVT iterations run, at every resolution
    int coarse_iterations = 0;        // of those, the ones run at a lower resolution (Lloyd)
    double final_movement = 0.0;      // largest site movement of the last iteration (radians)
    std::vector<glm::dvec3> sites;    // the sites texel_cell was assigned to (one per cell; CCVT's
                                      // cells are their power cells up to the texels balance_texels moved)
    std::vector<double> site_bias;    // CCVT's power-diagram biases (nearest_site.h); empty otherwise
    bool uniform_importance = false;  // the map was black: importance fell back to solid angle
};

// Throws UsageError for lights outside 1..kMaxLights and InputError when the hemisphere has fewer
// texels than lights. Deterministic for a given seed, whatever the number of threads. With
// Hemisphere::upper every cell is made of texels above the horizon only (its L~, dw, centre and caps).
Decomposition decompose(const EnvironmentMap& map, const DecomposeOptions& options);

// The per-cell integration every method ends with (docs/DESIGN.md §3), from the texel -> cell assignment of
// the texels `importance` holds (its rows; solid angles as it has them):
// radiance = sum L dw (RGB), solid_angle = sum dw, direction = normalised sum I w (sum dw w where the
// cell has no importance), cos_radius = 1 - dw_i / (2 pi), cos_radius_weighted = 2 (sum I (w . c) / sum I) - 1
// (solid-angle weighted where the cell has no importance). A cell whose mean direction vanishes (one
// cell over a uniform sphere) or that is empty takes `sites[k]` as its direction.
std::vector<Cell> integrate_cells(const EnvironmentMap& map, const ImportanceMap& importance,
                                  std::span<const std::uint16_t> texel_cell, std::span<const glm::dvec3> sites);

}  // namespace envshadow
