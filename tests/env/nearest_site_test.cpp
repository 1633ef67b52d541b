#include "env/nearest_site.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <random>

#include "env/importance.h"
#include "env/latlong.h"
#include "env_test_data.h"

namespace envshadow {
namespace {

std::vector<glm::dvec3> random_sites(int count, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> gauss;
    std::vector<glm::dvec3> sites;
    for (int k = 0; k < count; ++k) sites.push_back(glm::normalize(glm::dvec3(gauss(rng), gauss(rng), gauss(rng))));
    return sites;
}

std::vector<double> random_biases(int count, double scale, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-scale, scale);
    std::vector<double> bias;
    for (int k = 0; k < count; ++k) bias.push_back(u(rng));
    return bias;
}

void expect_same_assignment(const ImportanceMap& importance, const std::vector<glm::dvec3>& sites,
                            const std::vector<double>& bias) {
    std::vector<std::uint16_t> brute(importance.texel_count()), fast(importance.texel_count());
    assign_nearest_brute_force(importance, sites, bias, brute);
    NearestSiteSearch(importance).assign(sites, bias, fast);
    size_t differences = 0;
    for (size_t t = 0; t < brute.size(); ++t) differences += brute[t] != fast[t];
    EXPECT_EQ(differences, 0u) << importance.width << "x" << importance.height << ", " << sites.size() << " sites";
}

TEST(NearestSite, TileSearchEqualsBruteForceOnRealMaps) {
    for (const std::string name : {"city", "studio"}) {
        const ImportanceMap importance = build_importance(test::world(name));
        for (int count : {1, 2, 7, 64, 256}) {
            expect_same_assignment(importance, random_sites(count, 11 + count), {});
            // Power diagrams too (CCVT's biases).
            expect_same_assignment(importance, random_sites(count, 13 + count), random_biases(count, 0.02, count));
        }
    }
}

TEST(NearestSite, TileSearchEqualsBruteForceWithTiesAndTinyMaps) {
    for (const auto& [width, height] :
         {std::pair{2, 1}, std::pair{4, 2}, std::pair{6, 3}, std::pair{34, 17}, std::pair{130, 65}}) {
        EnvironmentMap map;
        map.width = width;
        map.height = height;
        map.texels.assign(size_t(width) * size_t(height), glm::vec3(1.0f));
        const ImportanceMap importance = build_importance(map);
        const int count = std::min(width * height, 40);
        expect_same_assignment(importance, random_sites(count, 3), {});
        // Sites on texel centres, with duplicates: ties go to the lower index in both.
        std::vector<glm::dvec3> on_texels;
        for (int k = 0; k < count; ++k) {
            const int t = (k * 7) % (width * height);
            on_texels.push_back(latlong::texel_direction(t % width, t / width, width, height));
        }
        on_texels.push_back(on_texels.front());
        on_texels.push_back(on_texels.back());
        expect_same_assignment(importance, on_texels, {});
    }
}

TEST(NearestSite, TileMomentsEqualTheMomentsOfTheBruteForceAssignment) {
    const ImportanceMap importance = build_importance(test::world("sunrise"));
    const std::vector<glm::dvec3> sites = random_sites(128, 5);
    const std::vector<double> bias = random_biases(128, 0.01, 6);
    std::vector<std::uint16_t> brute(importance.texel_count());
    assign_nearest_brute_force(importance, sites, bias, brute);
    const std::vector<CellMoments> expected = partition_moments(importance, brute, 128);
    const std::vector<CellMoments> moments = NearestSiteSearch(importance).moments(sites, bias);
    for (size_t k = 0; k < sites.size(); ++k) {
        EXPECT_NEAR(moments[k].importance, expected[k].importance, 1e-9 * importance.total);
        EXPECT_NEAR(moments[k].solid_angle, expected[k].solid_angle, 1e-9);
        EXPECT_NEAR(glm::length(moments[k].importance_direction - expected[k].importance_direction), 0.0,
                    1e-9 * importance.total);
    }
}

TEST(NearestSite, ResultsDoNotDependOnTheThreadCount) {
    const ImportanceMap importance = build_importance(test::world("forest"));
    const NearestSiteSearch search(importance);
    const std::vector<glm::dvec3> sites = random_sites(96, 9);
    std::vector<CellMoments> one, three;
    tbb::task_arena(1).execute([&] { one = search.moments(sites, {}); });
    tbb::task_arena(3).execute([&] { three = search.moments(sites, {}); });
    for (size_t k = 0; k < sites.size(); ++k) {
        EXPECT_EQ(one[k].importance, three[k].importance);
        EXPECT_EQ(one[k].importance_direction, three[k].importance_direction);
        EXPECT_EQ(one[k].solid_angle, three[k].solid_angle);
    }
}

}  // namespace
}  // namespace envshadow
