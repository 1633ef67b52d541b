#include "env/shading_normal.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace envshadow {

glm::dvec3 mirror_above_surface(const glm::dvec3& n, const glm::dvec3& ng, const glm::dvec3& view) {
    const double threshold = std::min(0.9 * glm::dot(ng, view), 0.01);
    // The mirror direction's height over the plane: reflect(-view, m) . ng.
    const auto mirror_height = [&](const glm::dvec3& m) {
        return 2.0 * glm::dot(m, view) * glm::dot(m, ng) - glm::dot(view, ng);
    };
    if (mirror_height(n) >= threshold) return n;
    glm::dvec3 x = n - glm::dot(n, ng) * ng;
    const double x_length = glm::length(x);
    if (!(x_length > 0.0)) return ng;
    x /= x_length;
    // ng (angle 0) clears the threshold, n (angle hi) does not: keep the last angle found to clear it.
    double lo = 0.0, hi = std::atan2(glm::dot(n, x), glm::dot(n, ng));
    for (int i = 0; i < kLiftSteps; ++i) {
        const double mid = 0.5 * (lo + hi);
        (mirror_height(std::cos(mid) * ng + std::sin(mid) * x) >= threshold ? lo : hi) = mid;
    }
    return std::cos(lo) * ng + std::sin(lo) * x;
}

}  // namespace envshadow
