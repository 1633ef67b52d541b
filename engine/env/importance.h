#pragma once
// Importance of an environment map's texels (docs/DESIGN.md §2): I = lum(L) * dw, dw the exact texel solid
// angle. The sampling and decomposition methods read only this; the map's RGB is read again by the
// per-cell integration.
#include <glm/vec3.hpp>
#include <vector>

#include "env/environment.h"

namespace envshadow {

// Directions of texel centres, from per-row and per-column tables of latlong::direction's factors:
// direction(i, j) equals latlong::texel_direction(i, j, W, H) bit for bit, without storing W x H vectors.
class TexelDirections {
public:
    TexelDirections() = default;
    TexelDirections(int width, int height);

    glm::dvec3 operator()(int i, int j) const {
        return {row_sin_[size_t(j)] * column_cos_[size_t(i)], row_cos_[size_t(j)],
                row_sin_[size_t(j)] * column_sin_[size_t(i)]};
    }

private:
    std::vector<double> row_sin_, row_cos_, column_cos_, column_sin_;
};

struct ImportanceMap {
    int width = 0, height = 0;
    std::vector<float> importance;        // I per texel (j * width + i), finite and >= 0
    std::vector<double> row_solid_angle;  // exact solid angle of one texel of row j
    TexelDirections directions;
    double total = 0.0;  // sum of I (> 0)
    // The map carries no luminance at all (all black): importance fell back to the texel solid
    // angle, so every method still gives well-defined cells (uniform by solid angle).
    bool uniform_fallback = false;

    float at(int i, int j) const { return importance[size_t(j) * size_t(width) + size_t(i)]; }
    std::size_t texel_count() const { return importance.size(); }
};

// Requires a valid map (finite, non-negative texels, W = 2H >= 2).
ImportanceMap build_importance(const EnvironmentMap& map);

// The same sphere at 1/factor of the resolution: the importance of factor x factor blocks of texels
// summed, exact solid angles and directions of the coarse texels. Requires factor to divide W and H.
ImportanceMap downsample_importance(const ImportanceMap& fine, int factor);

// The integral of L dw over the sphere, summed texel by texel (RGB, double precision).
glm::dvec3 integrate_radiance(const EnvironmentMap& map);

}  // namespace envshadow
