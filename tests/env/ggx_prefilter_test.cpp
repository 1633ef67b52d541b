// The GGX prefiltering of the split sum (env/ggx_prefilter.h) against its definition, docs/DESIGN.md §11:
// the direct numerical integral over the map's texels of L K(r . l), K(t) = D(sqrt((1 + t) / 2)) max(0, t),
// divided by K's integral over the sphere, each computed here with the test's own GGX and quadrature.
#include "env/ggx_prefilter.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "brdf/ggx_quadrature.h"
#include "env/latlong.h"
#include "env_test_data.h"

namespace envshadow {
namespace {

using testing::walter_ggx_distribution;
constexpr double kPi = std::numbers::pi;

double lobe(double t, double alpha) {
    return t > 0.0 ? walter_ggx_distribution(std::sqrt(0.5 * (1.0 + t)), alpha) * t : 0.0;
}

// integral of K over the sphere, 2 pi integral_0^(pi/2) K(cos theta) sin theta d theta by the midpoint rule.
double lobe_total(double alpha) {
    const int steps = 400000;
    double sum = 0.0;
    for (int s = 0; s < steps; ++s) {
        const double theta = 0.5 * kPi * (s + 0.5) / steps;
        sum += lobe(std::cos(theta), alpha) * std::sin(theta);
    }
    return 2.0 * kPi * sum * 0.5 * kPi / steps;
}

// The direct integral of L K(r . l) dl over the visible texels, over K's integral (`total`, lobe_total).
glm::dvec3 lobe_mean(const EnvironmentMap& map, const glm::dvec3& r, double alpha, double total,
                     Hemisphere hemisphere) {
    glm::dvec3 sum(0.0);
    for (int j = 0; j < map.height; ++j) {
        const double dw = hemisphere_texel_solid_angle(j, map.width, map.height, hemisphere);
        if (dw <= 0.0) continue;
        for (int i = 0; i < map.width; ++i) {
            const double k = lobe(glm::dot(r, latlong::texel_direction(i, j, map.width, map.height)), alpha);
            if (k > 0.0) sum += glm::dvec3(map.at(i, j)) * (k * dw);
        }
    }
    return sum / total;
}

using test::relative_error;
using test::test_directions;

TEST(GgxPrefilter, LobeFactorsMatchQuadrature) {
    for (double alpha : {1.0, 0.25, 1.0 / 64.0}) {
        const std::vector<double> factors = ggx_lobe_factors(alpha, 300);
        ASSERT_EQ(factors.size(), 301u);
        EXPECT_DOUBLE_EQ(factors[0], 1.0);
        for (int l : {1, 2, 5, 12, 60, 300}) {
            // integral_0^1 K(t) P_l(t) dt / integral_0^1 K(t) dt by the midpoint rule in theta, P_l by Bonnet.
            const int steps = 400000;
            double sum = 0.0, total = 0.0;
            for (int s = 0; s < steps; ++s) {
                const double theta = 0.5 * kPi * (s + 0.5) / steps, t = std::cos(theta);
                double p0 = 1.0, p1 = t;
                for (int k = 1; k < l; ++k) {
                    const double p2 = ((2.0 * k + 1.0) * t * p1 - k * p0) / (k + 1.0);
                    p0 = p1;
                    p1 = p2;
                }
                const double weight = lobe(t, alpha) * std::sin(theta);
                sum += weight * p1;
                total += weight;
            }
            EXPECT_NEAR(factors[std::size_t(l)], sum / total, 1e-6) << "l " << l << " alpha " << alpha;
        }
    }
}

TEST(GgxPrefilter, ConstantMapIsItsRadianceEverywhere) {
    const GgxPrefilteredEnvironment env =
        prefilter_environment_ggx(load_environment("builtin:constant:2"), Hemisphere::full);
    ASSERT_EQ(env.levels.size(), std::size_t(kGgxPrefilterLevels));
    EXPECT_FLOAT_EQ(env.levels.front().roughness, kGgxPrefilterMinRoughness);
    EXPECT_FLOAT_EQ(env.levels.back().roughness, 1.0f);
    // The sharpest levels keep degrees up to 511 whose row sums over the 512 rows are not quite zero for a
    // constant map (quadrature of P_l): 0.33% measured at roughness 0.125, under 0.2% from 0.2 on.
    for (const glm::dvec3& d : test_directions())
        for (float roughness : {0.0f, 0.125f, 0.2f, 0.5f, 0.77f, 1.0f})
            EXPECT_NEAR(env.radiance(d, roughness).g, 2.0, (roughness <= 0.125f ? 4e-3 : 2e-3) * 2.0) << roughness;
}

// 1024 x 512 (the convolution's own size, so that the direct sum sees the texels it sees): a sky brightening
// towards the zenith, a darker ground, a sun of radius 0.03 rad at 1000 times the sky and a coloured band.
EnvironmentMap synthetic_map() {
    EnvironmentMap map;
    map.width = 1024;
    map.height = 512;
    map.source = "synthetic";
    map.texels.resize(std::size_t(map.width) * std::size_t(map.height));
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.3, 0.8, -0.5));
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i) {
            const glm::dvec3 d = latlong::texel_direction(i, j, map.width, map.height);
            glm::dvec3 l = d.y > 0.0 ? glm::dvec3(0.2, 0.3, 0.5) * (0.5 + 0.5 * d.y) : glm::dvec3(0.06, 0.05, 0.04);
            if (glm::dot(d, sun) > std::cos(0.03)) l += glm::dvec3(300.0, 280.0, 250.0);
            if (std::abs(d.y - 0.1) < 0.05 && d.x > 0.5) l += glm::dvec3(2.0, 0.5, 0.1);
            map.at(i, j) = glm::vec3(l);
        }
    return map;
}

// Worst relative error (luminance) over the test directions plus the sun's and one 0.05 rad beside it, at the
// levels' roughnesses (within 1%) and between levels (linear in log roughness; within 10%).
void expect_matches_integration(const EnvironmentMap& map, Hemisphere hemisphere) {
    const GgxPrefilteredEnvironment env = prefilter_environment_ggx(map, hemisphere);
    std::vector<glm::dvec3> directions = test_directions();
    directions.push_back(glm::normalize(glm::dvec3(0.3, 0.8, -0.5)));
    directions.push_back(glm::normalize(glm::dvec3(0.3, 0.8, -0.5) + glm::dvec3(0.05, 0.0, 0.0)));
    for (const auto& [roughness, tolerance] : std::vector<std::pair<double, double>>{
             {0.125, 0.01}, {0.25, 0.01}, {0.5, 0.01}, {1.0, 0.01}, {0.18, 0.1}, {0.7, 0.1}}) {
        const double alpha = roughness * roughness, total = lobe_total(alpha);
        double worst = 0.0;
        for (const glm::dvec3& d : directions) {
            if (hemisphere == Hemisphere::upper && d.y < 0.0) continue;
            const double error =
                relative_error(env.radiance(d, float(roughness)), lobe_mean(map, d, alpha, total, hemisphere));
            EXPECT_LT(error, tolerance) << map.source << " roughness " << roughness << " at " << d.x << "," << d.y
                                        << "," << d.z;
            worst = std::max(worst, error);
        }
        std::printf("%s roughness %.3f: worst relative error %.2e\n", map.source.c_str(), roughness, worst);
    }
}

TEST(GgxPrefilter, MatchesIntegrationSynthetic) {
    expect_matches_integration(synthetic_map(), Hemisphere::full);
}
TEST(GgxPrefilter, MatchesIntegrationSyntheticUpper) {
    expect_matches_integration(synthetic_map(), Hemisphere::upper);
}
TEST(GgxPrefilter, MatchesIntegrationCity) {
    expect_matches_integration(test::world("city"), Hemisphere::full);
}

}  // namespace
}  // namespace envshadow
