// Prefiltering the environment for the ratio estimator (docs/DESIGN.md §4.1): the Phong lobes' levels, convolved
// through spherical harmonics by env/lobe_convolution.h. The Phong lobe's Funk-Hecke factor falls like
// exp(-l^2 / 2n), so level n needs l up to ~4.5 sqrt(n); its grid follows the lobe's width (texel spacing ~ a
// quarter of 1 / sqrt(n), where bilinear lookups err < 1%).
#include "env/prefilter.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <numbers>
#include <utility>

#include "env/lobe_convolution.h"
#include "env/prefilter_levels.h"

namespace envshadow {

namespace {

using prefiltering::kLevels;
using prefiltering::kMaxGridWidth;
using prefiltering::level_shininess;
constexpr double kPi = std::numbers::pi;
constexpr int kMinGridWidth = 64;        // E (n = 1): 64 x 32
constexpr double kTexelsPerLobe = 32.0;  // grid width ~ 32 sqrt(n) (spacing ~ 0.2 / sqrt(n)): 24 left 4% at n = 100

int next_power_of_two(int x) {
    return int(std::bit_ceil(unsigned(std::max(x, 1))));
}

}  // namespace

double phong_lobe_factor(int l, double n) {
    // Gradshteyn & Ryzhik 7.126.2: integral_0^1 t^n P_l(t) dt =
    //   sqrt(pi) 2^{-n-1} Gamma(n+1) / (Gamma(1 + n/2 - l/2) Gamma(n/2 + l/2 + 3/2)); 1/Gamma is 0 at the poles.
    const double x = 1.0 + 0.5 * n - 0.5 * l;
    double sign = 1.0;
    if (x <= 0.0) {
        if (x == std::floor(x)) return 0.0;
        sign = (int(std::ceil(-x)) % 2 == 1) ? -1.0 : 1.0;  // Gamma's sign on (-k, -k + 1)
    }
    const double log_value = 0.5 * std::log(kPi) - (n + 1.0) * std::log(2.0) + std::lgamma(n + 1.0) - std::lgamma(x) -
                             std::lgamma(0.5 * n + 0.5 * l + 1.5);
    return 2.0 * kPi * sign * std::exp(log_value);
}

PrefilteredEnvironment prefilter_environment(const EnvironmentMap& map, Hemisphere hemisphere) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<prefiltering::LobePlan> plans;
    for (int k = 0; k < kLevels; ++k) {
        const double n = level_shininess(k);
        prefiltering::LobePlan& plan = plans.emplace_back();
        plan.width =
            std::clamp(next_power_of_two(int(std::ceil(kTexelsPerLobe * std::sqrt(n)))), kMinGridWidth, kMaxGridWidth);
        plan.band = std::min(int(std::ceil(4.5 * std::sqrt(n) + 24.0)), plan.width / 2 - 1);
        for (int l = 0; l <= plan.band; ++l) plan.factors.push_back(phong_lobe_factor(l, n) * (n + 1.0) / (2.0 * kPi));
    }
    std::vector<prefiltering::LobeGrid> grids = prefiltering::convolve_with_lobes(map, hemisphere, plans);
    PrefilteredEnvironment result;
    for (int k = 0; k < kLevels; ++k) {
        PrefilteredLevel& level = result.levels.emplace_back();
        level.shininess = float(level_shininess(k));
        level.width = grids[std::size_t(k)].width;
        level.height = grids[std::size_t(k)].height;
        level.texels = std::move(grids[std::size_t(k)].texels);
    }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace envshadow
