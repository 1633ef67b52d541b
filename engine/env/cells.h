#pragma once
// Directional cells of an environment map (DESIGN.md §3): the output of every decomposition method,
// and what the renderer turns into lights.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "env/environment.h"

namespace envshadow {

struct Cell {
    glm::vec3 direction{0.0f, 1.0f, 0.0f};  // unit vector, map space (rotate by the scene's env rotation)
    glm::vec3 radiance{0.0f};               // L~_i = sum over the cell's texels of L dw (RGB)
    float solid_angle = 0.0f;               // dw_i = sum of texel solid angles
    float cos_radius = 1.0f;                // paper's cap: 1 - dw_i / (2 pi)
    float cos_radius_weighted = 1.0f;       // radiance-weighted cap: 2 (sum I (w.c) / sum I) - 1
};

enum class Method { lloyd, ccvt, mediancut, random, fs };
std::string_view to_string(Method method);
Method parse_method(std::string_view name);  // throws UsageError

struct DecomposeOptions {
    Method method = Method::lloyd;
    int lights = 128;        // 1..256 (mediancut rounds to a power of two)
    std::uint64_t seed = 1;
};

struct Decomposition {
    Method method = Method::lloyd;
    int width = 0, height = 0;
    std::vector<Cell> cells;
    std::vector<std::uint16_t> texel_cell;  // cell index of every texel (j * width + i)
    glm::dvec3 integral{0.0};               // integral of L dw computed directly from the map
    double seconds = 0.0;
    int iterations = 0;                     // Lloyd / CCVT iterations run
    double final_movement = 0.0;            // largest site movement of the last iteration (radians)
};

Decomposition decompose(const EnvironmentMap& map, const DecomposeOptions& options);

}  // namespace envshadow
