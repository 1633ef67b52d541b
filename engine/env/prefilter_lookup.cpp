// Lookups in the prefiltered levels: bilinear within a level, linear in log n between two.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "env/latlong.h"
#include "env/prefilter.h"
#include "env/prefilter_levels.h"

namespace envshadow {
namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

LevelPair PrefilteredEnvironment::level_pair(float shininess) const {
    const int last = int(levels.size()) - 1;
    if (last <= 0) return {};
    const double n = std::clamp(double(shininess), double(kPrefilterMinShininess), double(kPrefilterMaxShininess));
    const double t = std::clamp(prefiltering::level_coordinate(n), 0.0, double(last));
    const int lower = std::min(int(std::floor(t + 1e-9)), last - 1);  // n = 1000 lands on its level, not below
    return {lower, lower + 1, float(std::clamp(t - lower, 0.0, 1.0))};
}

glm::vec3 PrefilteredEnvironment::sample(int level, const glm::dvec3& direction) const {
    const PrefilteredLevel& g = levels[std::size_t(level)];
    const glm::dvec2 uv = latlong::uv(direction);
    const double x = uv.x * g.width - 0.5, y = uv.y * (g.height - 1);
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    const int i0 = (int(fx) % g.width + g.width) % g.width, i1 = (i0 + 1) % g.width;
    const int j0 = int(fy), j1 = std::min(j0 + 1, g.height - 1);
    auto at = [&](int i, int j) {
        return glm::dvec3(g.texels[std::size_t(j) * std::size_t(g.width) + std::size_t(i)]);
    };
    const glm::dvec3 top = at(i0, j0) * (1.0 - ax) + at(i1, j0) * ax;
    const glm::dvec3 bottom = at(i0, j1) * (1.0 - ax) + at(i1, j1) * ax;
    return glm::vec3(top * (1.0 - ay) + bottom * ay);
}

glm::vec3 PrefilteredEnvironment::irradiance(const glm::dvec3& n) const {
    return float(kPi) * sample(0, n);  // S_1 = E; level 0 stores S_1 (1 + 1) / (2 pi)
}

glm::vec3 PrefilteredEnvironment::specular(const glm::dvec3& r, float shininess) const {
    const LevelPair pair = level_pair(shininess);
    const glm::vec3 mean = sample(pair.lower, r) * (1.0f - pair.weight) + sample(pair.upper, r) * pair.weight;
    return mean * float(2.0 * kPi / (double(shininess) + 1.0));
}

}  // namespace envshadow
