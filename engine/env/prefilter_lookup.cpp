// Lookups in the prefiltered levels: bilinear within a level, linear in log n between two.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "env/lobe_convolution.h"
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
    return prefiltering::sample_grid(g.width, g.height, g.texels.data(), direction);
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
