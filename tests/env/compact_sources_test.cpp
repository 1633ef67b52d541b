// The compact sources taken out of a map (env/compact_sources.h): what is taken is what the sources carry, they
// sit where the bright texels are, and nothing else is touched.
#include "env/compact_sources.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "env/latlong.h"

namespace envshadow {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// A sky of radiance `sky` with, per disc, texels within `radius_degrees` of `centre` set to `radiance`.
struct Disc {
    glm::dvec3 centre;
    double radius_degrees;
    glm::vec3 radiance;
};
EnvironmentMap sky_with_discs(glm::vec3 sky, std::initializer_list<Disc> discs, int width = 512) {
    EnvironmentMap map{width, width / 2, {}, "test"};
    map.texels.assign(std::size_t(map.width) * std::size_t(map.height), sky);
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i)
            for (const Disc& disc : discs)
                if (glm::dot(latlong::texel_direction(i, j, map.width, map.height), glm::normalize(disc.centre)) >
                    std::cos(disc.radius_degrees * kDegree))
                    map.at(i, j) = disc.radiance;
    return map;
}

glm::dvec3 integral(const EnvironmentMap& map) {
    glm::dvec3 sum(0.0);
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i)
            sum += glm::dvec3(map.at(i, j)) * latlong::texel_solid_angle(j, map.width, map.height);
    return sum;
}

TEST(CompactSources, CarryWhatTheyTakeFromTheMap) {
    const glm::dvec3 sun_direction = glm::normalize(glm::dvec3(0.4, 0.8, -0.3));
    const EnvironmentMap map = sky_with_discs(glm::vec3(1.0f, 1.2f, 1.5f), {{sun_direction, 2.0, {4000, 3000, 2000}}});
    const CompactSourceSplit split = split_compact_sources(map, Hemisphere::full);
    ASSERT_EQ(split.sources.size(), 1u);
    const CompactSource& sun = split.sources[0];
    const glm::dvec3 total = integral(split.rest) + glm::dvec3(sun.radiance);
    const glm::dvec3 expected = integral(map);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(total[c], expected[c], 1e-6 * expected[c]);
    // The source takes the disc's texels whole, the sky under it too: its light is the map's less the sky's
    // outside the disc, and the disc's centre is black in the rest.
    EXPECT_GT(sun.radiance.g, 0.99 * (expected.g - 1.2 * 4.0 * std::numbers::pi));
    const glm::dvec2 centre = latlong::uv(sun_direction);
    EXPECT_EQ(split.rest.at(int(centre.x * map.width), int(centre.y * map.height)), glm::vec3(0.0f));
    EXPECT_GT(glm::dot(glm::dvec3(sun.direction), sun_direction), std::cos(0.1 * kDegree));
    // A uniform disc of radius 2 degrees: the cap of its mean cosine is the disc.
    EXPECT_NEAR(std::acos(sun.cos_radius) / kDegree, 2.0, 0.25);
    // The rest is the sky everywhere but the disc, and black there.
    EXPECT_EQ(split.rest.at(0, split.rest.height - 1), map.at(0, map.height - 1));
    for (const glm::vec3& texel : split.rest.texels) EXPECT_TRUE(texel.g == 0.0f || texel.g == 1.2f);
}

TEST(CompactSources, SitAtTheCentreOfTheLightTheyTake) {
    // A sun with a glow on one side, the glow at twice the threshold (about 4.1): the source takes both whole,
    // so its direction is their light's centre, not the centre of the excess over the threshold (0.25 degrees
    // nearer the core here).
    const glm::dvec3 core = glm::normalize(glm::dvec3(0.3, 0.9, -0.2));
    const glm::dvec3 side = glm::normalize(glm::cross(core, glm::dvec3(0.0, 0.0, 1.0)));
    const glm::dvec3 glow = std::cos(3.0 * kDegree) * core + std::sin(3.0 * kDegree) * side;
    const double core_radiance = 100.0, glow_radiance = 8.0;
    const EnvironmentMap map = sky_with_discs(
        glm::vec3(1.0f), {{glow, 2.0, glm::vec3(float(glow_radiance))}, {core, 1.0, glm::vec3(float(core_radiance))}},
        2048);
    const CompactSourceSplit split = split_compact_sources(map, Hemisphere::full);
    ASSERT_EQ(split.sources.size(), 1u);
    const auto cap = [](double radius_degrees) {
        return 2.0 * std::numbers::pi * (1.0 - std::cos(radius_degrees * kDegree));
    };
    const glm::dvec3 expected = glm::normalize(core_radiance * cap(1.0) * core + glow_radiance * cap(2.0) * glow);
    EXPECT_LT(std::acos(std::min(1.0, glm::dot(glm::dvec3(split.sources[0].direction), expected))) / kDegree, 0.06);
}

TEST(CompactSources, AreTheBrightestFourSmallOnes) {
    // Six suns of increasing power, and a bright region too wide to be a source (10 degrees).
    std::initializer_list<Disc> discs = {
        {{1, 0.5, 0}, 1.0, {2000, 2000, 2000}},  {{0, 0.5, 1}, 1.0, {3000, 3000, 3000}},
        {{-1, 0.5, 0}, 1.0, {4000, 4000, 4000}}, {{0, 0.5, -1}, 1.0, {5000, 5000, 5000}},
        {{1, 1, 1}, 1.0, {6000, 6000, 6000}},    {{-1, 1, -1}, 1.0, {7000, 7000, 7000}},
        {{0, -1, 0}, 10.0, {100, 100, 100}}};
    const EnvironmentMap map = sky_with_discs(glm::vec3(1.0f), discs);
    const CompactSourceSplit split = split_compact_sources(map, Hemisphere::full);
    ASSERT_EQ(split.sources.size(), std::size_t(kMaxCompactSources));
    const glm::dvec3 brightest[] = {{-1, 1, -1}, {1, 1, 1}, {0, 0.5, -1}, {-1, 0.5, 0}};
    for (int k = 0; k < kMaxCompactSources; ++k)
        EXPECT_GT(glm::dot(glm::dvec3(split.sources[std::size_t(k)].direction), glm::normalize(brightest[k])), 0.999)
            << k;
    // The two dimmest suns and the wide region stay in the map.
    EXPECT_EQ(split.rest.at(0, split.rest.height - 1), map.at(0, map.height - 1));
    const glm::dvec2 kept = latlong::uv(glm::normalize(glm::dvec3(1, 0.5, 0)));
    EXPECT_EQ(split.rest.at(int(kept.x * map.width), int(kept.y * map.height)), glm::vec3(2000.0f));
}

TEST(CompactSources, LeaveAMapWithoutAnyAlone) {
    const EnvironmentMap gradient = [] {
        EnvironmentMap map = sky_with_discs(glm::vec3(1.0f), {});
        for (int j = 0; j < map.height; ++j)
            for (int i = 0; i < map.width; ++i) map.at(i, j) = glm::vec3(1.0f + float(j) / float(map.height));
        return map;
    }();
    const CompactSourceSplit split = split_compact_sources(gradient, Hemisphere::full);
    EXPECT_TRUE(split.sources.empty());
    EXPECT_EQ(split.rest.texels, gradient.texels);
    const EnvironmentMap black = sky_with_discs(glm::vec3(0.0f), {});
    EXPECT_TRUE(split_compact_sources(black, Hemisphere::full).sources.empty());
}

TEST(CompactSources, AreAboveTheHorizonForTheUpperHemisphere) {
    const EnvironmentMap map = sky_with_discs(
        glm::vec3(1.0f), {{{0.3, -0.5, 0.2}, 1.0, {9000, 9000, 9000}}, {{0, 1, 1}, 1.0, {3000, 3000, 3000}}});
    const CompactSourceSplit split = split_compact_sources(map, Hemisphere::upper);
    ASSERT_EQ(split.sources.size(), 1u);
    EXPECT_GT(split.sources[0].direction.y, 0.0f);
    ASSERT_EQ(split_compact_sources(map, Hemisphere::full).sources.size(), 2u);
}

}  // namespace
}  // namespace envshadow
