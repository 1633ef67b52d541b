#pragma once
// Cells of the environment become the renderer's directional lights: rotated into the world, the
// ones that cannot change the image dropped, and packed for the GPU. Plain C++, no GL.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "env/cells.h"

namespace envshadow::render {

// A light's neighbourhood as a bit set over the lights: bit j of word j / 32 is set when light j is the
// light itself or one of its neighbours (light_neighbourhoods).
inline constexpr int kNeighbourhoodWords = kMaxLights / 32;
using Neighbourhood = std::array<std::uint32_t, kNeighbourhoodWords>;

// The GPU's light record: the C++ twin of `struct Light` in glsl/cells.glsl (std430).
struct LightRecord {
    glm::vec4 direction{0.0f, 1.0f, 0.0f, 1.0f};  // xyz: w_i in the world (towards the light); w: cos r_i
    glm::vec4 radiance{0.0f};                     // rgb: L~_i; w: 1 where the neighbourhood surrounds the light
    glm::mat4 clip_from_world{1.0f};              // the cell's orthographic projection (tile clip cube)
    glm::vec4 tile{0.0f};                         // xy: tile corner in atlas uv, zw: tile size in atlas uv
    glm::vec4 bias{
        0.0f};  // x: receiver depth bias (depth units), y: normal offset (world), zw: penumbra texels per depth
    Neighbourhood neighbourhood{};  // light_neighbourhoods' set: GLSL's uvec4[MAX_LIGHTS / 128], four words a vector
};
static_assert(sizeof(LightRecord) == 160, "must match the std430 layout of glsl/cells.glsl's Light");
static_assert(offsetof(LightRecord, neighbourhood) % 16 == 0, "GLSL's uvec4 array starts on a vec4");

// A light in the world, before shadow fitting.
struct WorldLight {
    glm::vec3 direction{0.0f, 1.0f, 0.0f};
    glm::vec3 radiance{0.0f};
    float cos_radius = 1.0f;           // the paper's solid-angle cap
    float cos_radius_weighted = 1.0f;  // the radiance-weighted cap
};

struct LightSelection {
    std::vector<WorldLight> kept;
    int below_ground = 0;  // hidden by the ground plane
    int negligible = 0;    // no radiance worth a shadow map
};

// Share of the total luminance that all dropped "negligible" lights may carry together.
inline constexpr double kNegligibleShare = 1e-6;

// Rotates the cells into the world (world_from_map, env/orientation.h) and, when `skip` is set,
// drops the lights that cannot change the image measurably:
//  - below the ground (scene has a ground plane and w_i.y < 0): the ground hides the cell's centre
//    from every point above it, so V = 0 wherever a(.) is non-zero (points on the ground face away
//    from it); dropping it changes nothing, it only saves a tile and the shader's loop. Cells of the
//    upper hemisphere (what a scene with a ground decomposes, docs/DESIGN.md §3.1) are never dropped here;
//    the check stays for cells of the whole sphere;
//  - negligible: the dimmest lights, in increasing luminance, as long as together they carry at most
//    kNegligibleShare of the total luminance (zero-radiance cells always). A pixel changes by at
//    most that share of what the unshadowed environment would give it (times the ratio of the
//    material's peak reflectivity to its mean), far under half-float precision and PNG quantisation.
LightSelection select_lights(std::span<const Cell> cells, const glm::mat3& world_from_map, bool has_ground, bool skip);

// How far apart, in units of the sum of two lights' cap radii, their centres may lie and the two still
// be neighbours. Equal-area caps (cos_radius) of Voronoi cells in a hexagonal arrangement put the first
// ring of neighbours at 0.95 (r_i + r_j) and the second at 1.65; 2 reaches the first ring of long cells
// too (those along the horizon of an upper hemisphere, a small cell beside the sun) and a centre off its
// cell's middle (the importance-weighted direction).
inline constexpr float kNeighbourReach = 2.0f;

// The widest gap, in azimuth about a light, that its neighbours may leave and still surround it.
inline constexpr float kSurroundingGapDegrees = 120.0f;

struct LightNeighbourhood {
    Neighbourhood lights{};   // the light itself and its neighbours
    bool surrounded = false;  // no gap wider than kSurroundingGapDegrees between the neighbours about it
};

// Each light's neighbourhood: itself and every light whose centre lies within kNeighbourReach (r_i + r_j)
// of its own, r the equal-area cap radius (acos cos_radius). The soft shadows' bound reads it: the cap of a
// surrounded light lies within the directions of its neighbours' centres, so where none of them sees a
// point, no part of the cap does (docs/DESIGN.md §5.9). When no light lies below the horizon (a scene with
// a ground, or a map dark there), the horizon closes a light's neighbourhood below: no light comes from
// there. At most kMaxLights lights (std::invalid_argument).
std::vector<LightNeighbourhood> light_neighbourhoods(std::span<const WorldLight> lights);

// The sun among the lights (docs/DESIGN.md §5.14, the sun per pixel): the index of the record of greatest
// luminance of L~ if it holds at least kSunShare times an even share of all of them, else -1 (no light
// stands out: a uniform or overcast sky).
inline constexpr double kSunShare = 2.0;
int sun_light(std::span<const LightRecord> lights);

}  // namespace envshadow::render
