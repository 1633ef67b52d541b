#include "env/shading_normal.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace envshadow {

glm::dvec3 mirror_above_surface(const glm::dvec3& n, const glm::dvec3& ng, const glm::dvec3& view) {
    const double vz = glm::dot(view, ng);
    const double threshold = std::min(0.9 * vz, 0.01);
    if (2.0 * glm::dot(n, view) * glm::dot(n, ng) - vz >= threshold) return n;  // reflect(-view, n) . ng
    glm::dvec3 x = n - glm::dot(n, ng) * ng;
    const double x_length = glm::length(x);
    if (!(x_length > 0.0)) return ng;
    x /= x_length;
    const double vx = glm::dot(view, x);
    const double r = std::sqrt(vz * vz + vx * vx);
    const double a = 0.5 * (std::atan2(vx, vz) + std::acos(std::clamp(threshold / r, -1.0, 1.0)));
    return std::cos(a) * ng + std::sin(a) * x;
}

}  // namespace envshadow
