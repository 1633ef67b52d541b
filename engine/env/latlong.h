#pragma once
// The one place the lat-long convention is written (docs/DESIGN.md §2; glsl/latlong.glsl mirrors it and a
// GL test keeps the two equal). World space is right-handed, +Y up.
//   Map W x H, texel (i, j) centre u = (i + 0.5) / W, v = (j + 0.5) / H; row 0 is the zenith.
//   theta = pi v (from +Y), phi = 2 pi u, direction = (sin theta cos phi, cos theta, sin theta sin phi).
// Looking along +X with +Y up, +Z is to the right, so u grows to the right as seen from inside the
// sphere: the map is not mirrored.
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace envshadow::latlong {

inline constexpr double kPi = std::numbers::pi;

inline glm::dvec3 direction(double u, double v) {
    const double theta = kPi * v, phi = 2.0 * kPi * u;
    const double s = std::sin(theta);
    return {s * std::cos(phi), std::cos(theta), s * std::sin(phi)};
}

// u in [0, 1), v in [0, 1]. `d` must be unit length.
inline glm::dvec2 uv(const glm::dvec3& d) {
    double u = std::atan2(d.z, d.x) / (2.0 * kPi);
    if (u < 0.0) u += 1.0;
    if (u >= 1.0) u -= 1.0;
    const double v = std::acos(std::fmin(1.0, std::fmax(-1.0, d.y))) / kPi;
    return {u, v};
}

inline glm::dvec3 texel_direction(int i, int j, int width, int height) {
    return direction((i + 0.5) / width, (j + 0.5) / height);
}

// Exact solid angle of any texel in row j: (2 pi / W) (cos theta_top - cos theta_bottom). Rows sum to 4 pi.
inline double texel_solid_angle(int j, int width, int height) {
    const double top = kPi * j / height, bottom = kPi * (j + 1) / height;
    return (2.0 * kPi / width) * (std::cos(top) - std::cos(bottom));
}

// Rec. 709 luminance.
inline double luminance(const glm::dvec3& rgb) {
    return 0.2126 * rgb.r + 0.7152 * rgb.g + 0.0722 * rgb.b;
}

}  // namespace envshadow::latlong
