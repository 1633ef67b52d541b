// The GGX prefiltering of the split sum (docs/DESIGN.md §11), on the spherical-harmonic convolution of the
// Phong prefiltering (env/lobe_convolution.h).
#include "env/ggx_prefilter.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <numbers>
#include <utility>

#include "env/gltf_brdf.h"
#include "env/lobe_convolution.h"

namespace envshadow {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kMinGridWidth = 64;
// Grid width ~ 32 / alpha: the lobe's half width at half maximum, 1.29 alpha, spans ~6 texels, as the Phong
// levels' 32 sqrt(n) do for theirs.
constexpr double kTexelsPerAlpha = 32.0;
// Degrees whose factor is below this (relative to l = 0) are dropped.
constexpr double kFactorCutoff = 1e-6;

// 8-point Gauss-Legendre on [-1, 1].
constexpr double kNodes[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
constexpr double kWeights[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

}  // namespace

double ggx_prefilter_level_roughness(int k) {
    return double(kGgxPrefilterMinRoughness) * std::exp2(k / 5.0);
}

std::vector<double> ggx_lobe_factors(double alpha, int band) {
    // Over theta = acos t in [0, pi/2] (K is 0 beyond): Lambda_l = 2 pi integral K(cos theta) P_l(cos theta)
    // sin theta d theta, composite Gauss-Legendre on intervals narrower than half of alpha (the peak's width is
    // ~2 alpha) and than half a period of P_l (2 pi / l).
    const double step = std::min(0.5 * alpha, kPi / (band + 1.0));
    const int intervals = int(std::ceil(0.5 * kPi / step));
    const double h = 0.5 * kPi / intervals;
    std::vector<double> sums(std::size_t(band) + 1, 0.0);
    for (int k = 0; k < intervals; ++k) {
        const double middle = (k + 0.5) * h;
        for (int q = 0; q < 8; ++q) {
            const double theta = middle + 0.5 * h * (q < 4 ? -kNodes[q] : kNodes[q - 4]);
            const double t = std::cos(theta);
            const double weight = 0.5 * h * kWeights[q % 4] * std::sin(theta) * t *
                                  gltf_brdf::ggx_distribution(std::sqrt(0.5 * (1.0 + t)), alpha);
            double p0 = 1.0, p1 = t;  // Bonnet's recurrence
            sums[0] += weight;
            if (band >= 1) sums[1] += weight * t;
            for (int l = 1; l < band; ++l) {
                const double p2 = ((2.0 * l + 1.0) * t * p1 - l * p0) / (l + 1.0);
                p0 = p1;
                p1 = p2;
                sums[std::size_t(l) + 1] += weight * p2;
            }
        }
    }
    for (int l = band; l >= 0; --l) sums[std::size_t(l)] /= sums[0];
    return sums;
}

GgxPrefilteredEnvironment prefilter_environment_ggx(const EnvironmentMap& map, Hemisphere hemisphere) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<prefiltering::LobePlan> plans;
    for (int k = 0; k < kGgxPrefilterLevels; ++k) {
        const double alpha = gltf_brdf::alpha_from_roughness(ggx_prefilter_level_roughness(k));
        prefiltering::LobePlan& plan = plans.emplace_back();
        plan.width = std::clamp(int(std::bit_ceil(unsigned(std::ceil(kTexelsPerAlpha / alpha)))), kMinGridWidth,
                                prefiltering::kMaxGridWidth);
        plan.factors = ggx_lobe_factors(alpha, plan.width / 2 - 1);
        plan.band = int(plan.factors.size()) - 1;
        while (plan.band > 0 && std::abs(plan.factors[std::size_t(plan.band)]) < kFactorCutoff) --plan.band;
    }
    std::vector<prefiltering::LobeGrid> grids = prefiltering::convolve_with_lobes(map, hemisphere, plans);
    GgxPrefilteredEnvironment result;
    for (int k = 0; k < kGgxPrefilterLevels; ++k) {
        GgxPrefilteredLevel& level = result.levels.emplace_back();
        level.roughness = float(ggx_prefilter_level_roughness(k));
        level.width = grids[std::size_t(k)].width;
        level.height = grids[std::size_t(k)].height;
        level.texels = std::move(grids[std::size_t(k)].texels);
    }
    result.hemisphere = hemisphere;
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

glm::vec3 GgxPrefilteredEnvironment::sample(int level, const glm::dvec3& direction) const {
    const GgxPrefilteredLevel& g = levels[std::size_t(level)];
    return prefiltering::sample_grid(g.width, g.height, g.texels.data(), direction);
}

LevelPair GgxPrefilteredEnvironment::level_pair(float roughness) const {
    const int last = int(levels.size()) - 1;
    const double clamped = std::clamp(double(roughness), double(kGgxPrefilterMinRoughness), 1.0);
    const double t = std::clamp(5.0 * std::log2(clamped / kGgxPrefilterMinRoughness), 0.0, double(last));
    const int lower = std::min(int(std::floor(t + 1e-9)), std::max(last - 1, 0));
    const int upper = std::min(lower + 1, last);
    return {lower, upper, float(std::clamp(t - lower, 0.0, 1.0))};
}

float ggx_sharpest_level_weight(float roughness) {
    const float t = std::clamp(roughness / kGgxPrefilterMinRoughness, 0.0f, 1.0f);
    return t * t;
}

glm::vec3 GgxPrefilteredEnvironment::radiance(const glm::dvec3& r, float roughness) const {
    const LevelPair pair = level_pair(roughness);
    return sample(pair.lower, r) * (1.0f - pair.weight) + sample(pair.upper, r) * pair.weight;
}

}  // namespace envshadow
