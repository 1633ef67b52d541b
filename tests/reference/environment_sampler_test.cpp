// The reference's view of the environment: texel lookup and rotation, the filtered background lookup,
// and a sampler whose density is the map's luminance over solid angle.
#include "reference/environment_sampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "env/latlong.h"

namespace envshadow::testing {
namespace {

using reference::EnvironmentSampler;

// A map with a bright "sun" texel, a dark band, a black patch and smooth variation elsewhere.
EnvironmentMap test_map(int width = 32, int height = 16) {
    EnvironmentMap map;
    map.width = width;
    map.height = height;
    map.texels.resize(std::size_t(width) * std::size_t(height));
    for (int j = 0; j < height; ++j) {
        for (int i = 0; i < width; ++i) {
            const float u = (i + 0.5f) / width, v = (j + 0.5f) / height;
            map.at(i, j) = glm::vec3(0.5f + u, 1.5f - v, 0.25f + u * v);
        }
    }
    map.at(5, 3) = glm::vec3(400.0f, 300.0f, 200.0f);               // the sun
    for (int i = 10; i < 14; ++i) map.at(i, 12) = glm::vec3(0.0f);  // black: never sampled
    for (int i = 0; i < width; ++i) map.at(i, 8) *= 0.01f;          // a dark band
    map.source = "test";
    return map;
}

TEST(EnvironmentSampler, LooksUpTheTexelInTheRotatedMap) {
    const EnvironmentMap map = test_map();
    // No rotation: the direction of texel (i, j)'s centre gives that texel.
    const EnvironmentSampler plain(map, 0.0);
    for (int j = 0; j < map.height; j += 3) {
        for (int i = 0; i < map.width; i += 5) {
            const glm::dvec3 got = plain.radiance(latlong::texel_direction(i, j, map.width, map.height));
            EXPECT_EQ(got, glm::dvec3(map.at(i, j))) << i << "," << j;
        }
    }
    // Rotated 90 degrees about +Y (world = R map, right-handed: +X turns towards -Z): looking along -Z
    // one sees the map's +X, the u = 0 edge at the horizon; unrotated, -Z is u = 3/4.
    const EnvironmentSampler turned(map, 90.0);
    const glm::dvec3 towards_minus_z(1e-9, 0.0, -1.0);  // a hair towards +X so that u lands in column 0, not W-1
    EXPECT_EQ(turned.radiance(glm::normalize(towards_minus_z)), glm::dvec3(map.at(0, map.height / 2)));
    EXPECT_EQ(plain.radiance(glm::dvec3(0.0, 0.0, -1.0)), glm::dvec3(map.at(3 * map.width / 4, map.height / 2)));
    const glm::dvec3 x_in_world = reference::world_from_map(90.0) * glm::dvec3(1.0, 0.0, 0.0);
    EXPECT_NEAR(x_in_world.x, 0.0, 1e-12);
    EXPECT_NEAR(x_in_world.z, -1.0, 1e-12);
}

TEST(EnvironmentSampler, FilteredLookupIsBilinearBetweenTexelCentres) {
    // Radiance linear in v (constant along rows) is reproduced exactly between the first and last row centres.
    EnvironmentMap map;
    map.width = 16;
    map.height = 8;
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i) map.texels.push_back(glm::vec3(1.0f + 2.0f * (j + 0.5f) / map.height));
    const EnvironmentSampler sampler(map, 0.0);
    for (double v : {0.07, 0.2, 0.5, 0.77, 0.93}) {
        const glm::dvec3 d = latlong::direction(0.3, v);
        EXPECT_NEAR(sampler.radiance_filtered(d).r, 1.0 + 2.0 * v, 1e-5) << v;
    }
    // At a texel's centre it is that texel.
    const EnvironmentMap varied = test_map();
    const EnvironmentSampler varied_sampler(varied, 0.0);
    EXPECT_NEAR(varied_sampler.radiance_filtered(latlong::texel_direction(5, 3, varied.width, varied.height)).r, 400.0,
                1e-3);
}

// The sampled weight, written here from its definition: max(0, lum - mean).
double mean_of(const EnvironmentMap& map) {
    double integral = 0.0;
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i)
            integral +=
                latlong::luminance(glm::dvec3(map.at(i, j))) * latlong::texel_solid_angle(j, map.width, map.height);
    return integral / (4.0 * std::numbers::pi);
}
double excess(const glm::vec3& rgb, double mean) {
    return std::max(0.0, latlong::luminance(glm::dvec3(rgb)) - mean);
}
double excess_integral(const EnvironmentMap& map) {
    const double mean = mean_of(map);
    double integral = 0.0;
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i)
            integral += excess(map.at(i, j), mean) * latlong::texel_solid_angle(j, map.width, map.height);
    return integral;
}

TEST(EnvironmentSampler, DensityIsTheLightAboveTheMean) {
    const EnvironmentMap map = test_map();
    const EnvironmentSampler sampler(map, 30.0);
    const double mean = mean_of(map), integral = excess_integral(map);
    EXPECT_NEAR(sampler.mean_luminance(), mean, 1e-9 * mean);
    EXPECT_NEAR(sampler.luminance_integral(), 4.0 * std::numbers::pi * mean, 1e-9 * mean);
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (int k = 0; k < 2000; ++k) {
        const reference::EnvironmentSample s = sampler.sample(uniform(random), uniform(random));
        EXPECT_NEAR(glm::length(s.direction), 1.0, 1e-12);
        const double density = excess(glm::vec3(sampler.radiance(s.direction)), mean) / integral;
        EXPECT_GT(density, 0.0);  // only texels brighter than the mean are chosen
        EXPECT_NEAR(s.pdf, density, 1e-9 * density);
        EXPECT_NEAR(sampler.pdf(s.direction), density, 1e-9 * density);
        double looked_up = 0.0;
        EXPECT_EQ(sampler.radiance_and_pdf(s.direction, looked_up), sampler.radiance(s.direction));
        EXPECT_EQ(looked_up, sampler.pdf(s.direction));
    }
    // Texels at or below the mean have density 0: the dark band and the black patch.
    const glm::dmat3 world_from_map = reference::world_from_map(30.0);
    EXPECT_EQ(sampler.pdf(world_from_map * latlong::texel_direction(3, 8, map.width, map.height)), 0.0);
    EXPECT_EQ(sampler.pdf(world_from_map * latlong::texel_direction(11, 12, map.width, map.height)), 0.0);
}

TEST(EnvironmentSampler, EstimatesIntegralsWithoutBias) {
    // E[g / pdf] = integral of g over the sampled texels (those brighter than the mean): for g = the
    // radiance (RGB) and g = 1 (their solid angle), from stratified draws.
    const EnvironmentMap map = test_map();
    const EnvironmentSampler sampler(map, -45.0);
    const double mean = mean_of(map);
    glm::dvec3 integral(0.0);
    double bright_solid_angle = 0.0;
    for (int j = 0; j < map.height; ++j) {
        for (int i = 0; i < map.width; ++i) {
            if (excess(map.at(i, j), mean) <= 0.0) continue;
            const double dw = latlong::texel_solid_angle(j, map.width, map.height);
            integral += glm::dvec3(map.at(i, j)) * dw;
            bright_solid_angle += dw;
        }
    }
    std::mt19937_64 random(11);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const int count = 200000;
    glm::dvec3 estimate(0.0);
    double solid_angle = 0.0;
    for (int k = 0; k < count; ++k) {
        const reference::EnvironmentSample s =
            sampler.sample((k % 400 + uniform(random)) / 400.0, (k / 400 + uniform(random)) / 500.0);
        estimate += sampler.radiance(s.direction) / s.pdf / double(count);
        solid_angle += 1.0 / s.pdf / double(count);
    }
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(estimate[c] / integral[c], 1.0, 3e-3) << c;
    EXPECT_NEAR(solid_angle / bright_solid_angle, 1.0, 2e-2);
    EXPECT_GT(bright_solid_angle, 0.0);
}

TEST(EnvironmentSampler, StrataFollowTheImportanceOfTheTexels) {
    // The sun texel holds a known share of the sampled weight; a grid of points lands in it in that share.
    const EnvironmentMap map = test_map();
    const EnvironmentSampler sampler(map, 0.0);
    const double sun = excess(map.at(5, 3), mean_of(map)) * latlong::texel_solid_angle(3, map.width, map.height);
    const double share = sun / excess_integral(map);
    const int count = 10000;
    int hits = 0;
    for (int k = 0; k < count; ++k) {
        const glm::dvec3 d = sampler.sample((k % 100 + 0.5) / 100.0, (k / 100 + 0.5) / 100.0).direction;
        if (sampler.radiance(d) == glm::dvec3(map.at(5, 3))) ++hits;
    }
    EXPECT_NEAR(double(hits) / count, share, 0.02);  // a 100 x 100 grid of points: 1/100 per coordinate
    EXPECT_GT(share, 0.1);
}

TEST(EnvironmentSampler, BlackOrUniformMapsHaveNothingToSample) {
    EnvironmentMap map;
    map.width = 8;
    map.height = 4;
    map.texels.assign(32, glm::vec3(0.0f));
    const EnvironmentSampler black(map, 0.0);
    EXPECT_FALSE(black.can_sample());
    EXPECT_EQ(black.pdf(glm::dvec3(0, 1, 0)), 0.0);
    map.texels.assign(32, glm::vec3(3.0f));
    const EnvironmentSampler uniform(map, 0.0);
    EXPECT_FALSE(uniform.can_sample());  // nothing above the mean, despite rounding: the BRDF's strategies do it all
    EXPECT_NEAR(uniform.mean_luminance(), 3.0, 1e-12);
}

}  // namespace
}  // namespace envshadow::testing
