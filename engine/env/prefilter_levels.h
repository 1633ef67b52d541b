#pragma once
// The prefiltered levels' shininess values (env/prefilter.cpp builds them, the lookups interpolate
// between them; internal to the two).
#include <cmath>

namespace envshadow::prefiltering {

// n_k = 10^(k / 8) up to 1000 (1, 10, 100, 1000 exact; neighbours 1.33x apart), then 10^(1/4) apart up to
// 10^4: the sharp lobes' grids and bands cost the most.
constexpr int kFineLevels = 25;
constexpr int kLevels = kFineLevels + 4;
inline double level_shininess(int k) {
    return k < kFineLevels ? std::pow(10.0, k / 8.0) : std::pow(10.0, 3.0 + (k - kFineLevels + 1) / 4.0);
}
// The level coordinate of shininess n: k + fraction, linear in log n within each spacing.
inline double level_coordinate(double n) {
    const double decades = std::log10(n);
    return decades <= 3.0 ? decades * 8.0 : kFineLevels - 1 + (decades - 3.0) * 4.0;
}

}  // namespace envshadow::prefiltering
