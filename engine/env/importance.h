#pragma once
// Importance of an environment map's texels (docs/DESIGN.md §2): I = lum(L) * dw, dw the exact texel solid
// angle. The sampling and decomposition methods read only this; the map's RGB is read again by the
// per-cell integration.
#include <glm/vec3.hpp>
#include <vector>

#include "core/enum_names.h"
#include "env/environment.h"

namespace envshadow {

// Which directions a decomposition covers (docs/DESIGN.md §3.1): the whole sphere, or the hemisphere above
// the horizon (y >= 0), all that reaches an object standing on a ground plane.
enum class Hemisphere { full, upper };
inline constexpr EnumName<Hemisphere> kHemisphereNames[] = {{Hemisphere::full, "full"}, {Hemisphere::upper, "upper"}};
constexpr std::span<const EnumName<Hemisphere>> enum_names(Hemisphere) {
    return kHemisphereNames;
}

// The rows of a lat-long map of `height` rows (row 0 the zenith) that hold the hemisphere: all of them,
// or those above the horizon, ceil(H / 2). For H even the horizon lies between rows H/2 - 1 and H/2;
// for H odd it halves the middle row, which counts with the upper half of its solid angle.
int hemisphere_rows(int height, Hemisphere hemisphere);

// Solid angle of one texel of row j inside the hemisphere: latlong::texel_solid_angle, half of it for
// the middle row of an odd-height map cut by the horizon, 0 below the horizon.
double hemisphere_texel_solid_angle(int j, int width, int height, Hemisphere hemisphere);

// Directions of texel centres, from per-row and per-column tables of latlong::direction's factors:
// direction(i, j) equals latlong::texel_direction(i, j, W, H) bit for bit, without storing W x H vectors.
// `rows` (default: all) of the map's `height` are tabulated.
class TexelDirections {
public:
    TexelDirections() = default;
    TexelDirections(int width, int height, int rows = -1);

    glm::dvec3 operator()(int i, int j) const {
        return {row_sin_[size_t(j)] * column_cos_[size_t(i)], row_cos_[size_t(j)],
                row_sin_[size_t(j)] * column_sin_[size_t(i)]};
    }

private:
    std::vector<double> row_sin_, row_cos_, column_cos_, column_sin_;
};

// The importance of the texels of one hemisphere of a map: rows 0 .. height - 1 of a lat-long map of
// map_height rows (all of them for the full sphere; the rows above the horizon for the upper
// hemisphere), so that every method sees only the texels it decomposes. Directions and solid angles
// are those of the whole map's texels (the middle row of an odd map_height halved by the horizon).
struct ImportanceMap {
    int width = 0, height = 0;            // the texels held
    int map_height = 0;                   // rows of the whole lat-long map; 0: height (the whole sphere)
    std::vector<float> importance;        // I per texel (j * width + i), finite and >= 0
    std::vector<double> row_solid_angle;  // solid angle of one texel of row j (inside the hemisphere)
    TexelDirections directions;
    double total = 0.0;  // sum of I (> 0)
    // The map carries no luminance at all (all black): importance fell back to the texel solid
    // angle, so every method still gives well-defined cells (uniform by solid angle).
    bool uniform_fallback = false;

    float at(int i, int j) const { return importance[size_t(j) * size_t(width) + size_t(i)]; }
    std::size_t texel_count() const { return importance.size(); }
    // The rows of the whole map, which fix the texels' directions and solid angles.
    int lat_long_height() const { return map_height > 0 ? map_height : height; }
};

// Requires a valid map (finite, non-negative texels, W = 2H >= 2). The texels of `hemisphere` only.
ImportanceMap build_importance(const EnvironmentMap& map, Hemisphere hemisphere = Hemisphere::full);

// The same texels at 1/factor of the resolution: the importance of factor x factor blocks of texels
// summed, exact solid angles and directions of the coarse texels. Requires factor to divide W, the rows
// held and the map's rows.
ImportanceMap downsample_importance(const ImportanceMap& fine, int factor);

// The integral of L dw over the hemisphere, summed texel by texel (RGB, double precision).
glm::dvec3 integrate_radiance(const EnvironmentMap& map, Hemisphere hemisphere = Hemisphere::full);

}  // namespace envshadow
