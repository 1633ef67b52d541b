#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "common/ccvt_unsplittable.h"
#include "core/error.h"
#include "env/cell_overlay.h"
#include "env/cells.h"
#include "env/importance.h"
#include "env/latlong.h"
#include "env/nearest_site.h"
#include "env/sites.h"
#include "env_test_data.h"

namespace envshadow {
namespace {

constexpr double kFourPi = 4.0 * std::numbers::pi;

Decomposition run(const EnvironmentMap& map, Method method, int lights, std::uint64_t seed = 1) {
    DecomposeOptions options;
    options.method = method;
    options.lights = lights;
    options.seed = seed;
    return decompose(map, options);
}

int expected_cells(Method method, int lights) {
    if (method != Method::mediancut) return lights;
    int power = 1;
    while (2 * power <= lights) power *= 2;
    return power;
}

// The properties every decomposition has (docs/DESIGN.md §3), checked against values computed here.
void expect_valid(const EnvironmentMap& map, const Decomposition& d, const glm::dvec3& integral, Method method,
                  int lights, const std::string& label) {
    SCOPED_TRACE(label);
    const int cells = int(d.cells.size());
    if (method == Method::fs)
        EXPECT_LE(std::abs(cells - lights), 2);
    else
        EXPECT_EQ(cells, expected_cells(method, lights));
    // Every texel is in exactly one cell.
    ASSERT_EQ(d.texel_cell.size(), map.texels.size());
    EXPECT_LT(*std::max_element(d.texel_cell.begin(), d.texel_cell.end()), cells);
    glm::dvec3 radiance(0.0);
    double solid_angle = 0.0;
    for (const Cell& c : d.cells) {
        radiance += glm::dvec3(c.radiance);
        solid_angle += c.solid_angle;
        EXPECT_NEAR(glm::length(c.direction), 1.0f, 1e-5f);
        EXPECT_GE(c.cos_radius, -1.0f);
        EXPECT_LE(c.cos_radius, 1.0f);
        EXPECT_GE(c.cos_radius_weighted, -1.0f);
        EXPECT_LE(c.cos_radius_weighted, 1.0f);
        EXPECT_GE(c.solid_angle, 0.0f);
    }
    // Sum of cell radiance equals the integral of L dw; solid angles sum to 4 pi.
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(radiance[c], integral[c], 1e-4 * integral[c] + 1e-12);
        EXPECT_NEAR(d.integral[c], integral[c], 1e-9 * integral[c] + 1e-12);
    }
    EXPECT_NEAR(solid_angle, kFourPi, 1e-4 * kFourPi);
}

class Conservation : public ::testing::TestWithParam<std::string> {};

TEST_P(Conservation, EveryMethodAndLightCount) {
    const EnvironmentMap& map = test::world(GetParam());
    const glm::dvec3 integral = test::direct_integral(map);
    for (Method method : enum_values<Method>())
        for (int lights : {1, 16, 64, 128, 256})
            expect_valid(map, run(map, method, lights), integral, method, lights,
                         GetParam() + " " + std::string(to_string(method)) + " N=" + std::to_string(lights));
}

INSTANTIATE_TEST_SUITE_P(Maps, Conservation,
                         ::testing::Values("city", "courtyard", "forest", "interior", "night", "studio", "sunrise",
                                           "sunset", "builtin:constant", "builtin:sky"),
                         [](const auto& param_info) {
                             std::string name = param_info.param;
                             std::replace(name.begin(), name.end(), ':', '_');
                             return name;
                         });

TEST(Decompose, WhiteFurnaceGivesFourPiPerChannel) {
    const EnvironmentMap map = load_environment("builtin:constant");
    for (Method method : enum_values<Method>()) {
        glm::dvec3 sum(0.0);
        for (const Cell& c : run(map, method, 64).cells) sum += glm::dvec3(c.radiance);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c], kFourPi, 1e-4 * kFourPi) << to_string(method);
    }
}

// Each cell from its texels, recomputed here: the importance-weighted mean direction and both caps.
TEST(Decompose, CellsAreIntegratedFromTheirTexels) {
    const EnvironmentMap& map = test::world("interior");
    const Decomposition d = run(map, Method::lloyd, 32);
    std::vector<glm::dvec3> weighted(d.cells.size(), glm::dvec3(0.0));
    std::vector<double> importance(d.cells.size(), 0.0), solid_angle(d.cells.size(), 0.0);
    for (int j = 0; j < map.height; ++j) {
        const double dw = latlong::texel_solid_angle(j, map.width, map.height);
        for (int i = 0; i < map.width; ++i) {
            const size_t k = d.texel_cell[size_t(j) * size_t(map.width) + size_t(i)];
            const double I = latlong::luminance(glm::dvec3(map.at(i, j))) * dw;
            weighted[k] += I * latlong::texel_direction(i, j, map.width, map.height);
            importance[k] += I;
            solid_angle[k] += dw;
        }
    }
    for (size_t k = 0; k < d.cells.size(); ++k) {
        const glm::dvec3 centre = glm::normalize(weighted[k]);
        EXPECT_NEAR(glm::length(glm::dvec3(d.cells[k].direction) - centre), 0.0, 1e-5);
        EXPECT_NEAR(d.cells[k].solid_angle, solid_angle[k], 1e-5);
        EXPECT_NEAR(d.cells[k].cos_radius, 1.0 - solid_angle[k] / (2.0 * std::numbers::pi), 1e-5);
        EXPECT_NEAR(d.cells[k].cos_radius_weighted, 2.0 * glm::length(weighted[k]) / importance[k] - 1.0, 1e-4);
    }
}

// CCVT's cells are its power cells with whole texels then passed across their borders (balance_texels).
TEST(Decompose, CellsAreTheNearestSiteAssignment) {
    const EnvironmentMap& map = test::world("sunset");
    const ImportanceMap importance = build_importance(map);
    for (Method method : enum_values<Method>()) {
        const Decomposition d = run(map, method, 48);
        std::vector<std::uint16_t> brute(importance.texel_count());
        assign_nearest_brute_force(importance, d.sites, d.site_bias, brute);
        if (method == Method::ccvt) balance_texels(shareable_importance(importance, 48), brute, 48);
        EXPECT_EQ(brute, d.texel_cell) << to_string(method);
    }
}

TEST(Decompose, BruteForceSearchGivesTheSameCells) {
    const EnvironmentMap map = load_environment("builtin:sky:width=256");
    DecomposeOptions options;
    options.lights = 24;
    for (Method method : {Method::lloyd, Method::ccvt}) {
        options.method = method;
        options.search = SiteSearch::tiles;
        const Decomposition tiles = decompose(map, options);
        options.search = SiteSearch::brute_force;
        const Decomposition brute = decompose(map, options);
        EXPECT_EQ(tiles.texel_cell, brute.texel_cell) << to_string(method);
        EXPECT_EQ(tiles.iterations, brute.iterations);
    }
}

TEST(Decompose, SameSeedSameCellsWhateverTheThreadCount) {
    const EnvironmentMap& map = test::world("forest");
    for (Method method : {Method::lloyd, Method::ccvt, Method::random}) {
        Decomposition one, two;
        tbb::task_arena(1).execute([&] { one = run(map, method, 40, 7); });
        tbb::task_arena(2).execute([&] { two = run(map, method, 40, 7); });
        ASSERT_EQ(one.cells.size(), two.cells.size());
        for (size_t k = 0; k < one.cells.size(); ++k) {
            EXPECT_EQ(one.cells[k].direction, two.cells[k].direction) << to_string(method);
            EXPECT_EQ(one.cells[k].radiance, two.cells[k].radiance) << to_string(method);
        }
        EXPECT_EQ(one.texel_cell, two.texel_cell);
    }
    // And the seed matters where it is used.
    EXPECT_NE(run(map, Method::random, 40, 7).texel_cell, run(map, Method::random, 40, 8).texel_cell);
}

// Coefficient of variation of the cells' importance, leaving out cells that hold a texel heavier than
// an equal share (a sun cannot be split).
double importance_variation(const EnvironmentMap& map, const Decomposition& d) {
    const ImportanceMap importance = build_importance(map);
    const size_t n = d.cells.size();
    std::vector<double> mass(n, 0.0);
    std::vector<bool> holds_sun(n, false);
    const double threshold = test::unsplittable_threshold(std::span<const float>(importance.importance), int(n));
    for (size_t t = 0; t < importance.texel_count(); ++t) {
        mass[d.texel_cell[t]] += importance.importance[t];
        if (importance.importance[t] > threshold) holds_sun[d.texel_cell[t]] = true;
    }
    double sum = 0.0, squares = 0.0;
    int count = 0;
    for (size_t k = 0; k < n; ++k)
        if (!holds_sun[k]) {
            sum += mass[k];
            squares += mass[k] * mass[k];
            ++count;
        }
    const double mean = sum / count;
    return std::sqrt(std::max(0.0, squares / count - mean * mean)) / mean;
}

TEST(Ccvt, CellsCarryEqualImportanceOnEvenMaps) {
    for (const auto& [name, lights] :
         {std::pair{"courtyard", 16}, std::pair{"courtyard", 64}, std::pair{"studio", 16}, std::pair{"studio", 64}}) {
        const EnvironmentMap& map = test::world(name);
        EXPECT_LT(importance_variation(map, run(map, Method::ccvt, lights)), 0.10) << name << " N=" << lights;
    }
}

TEST(Ccvt, CellsWithoutTheSunCarryEqualImportance) {
    for (const auto& [name, lights] : {std::pair{"city", 16}, std::pair{"city", 64}, std::pair{"sunrise", 16}}) {
        const EnvironmentMap& map = test::world(name);
        const Decomposition d = run(map, Method::ccvt, lights);
        EXPECT_LT(importance_variation(map, d), 0.10) << name << " N=" << lights;
    }
}

// --- balance_texels on small synthetic maps, where the answer is known ---------------------------------

// A W x H importance map of the given texel weights (balance_texels reads only the sizes, weights and total).
ImportanceMap synthetic_importance(int width, int height, std::vector<float> weights) {
    ImportanceMap m;
    m.width = width;
    m.height = height;
    m.importance = std::move(weights);
    m.row_solid_angle.assign(size_t(height), 4.0 * std::numbers::pi / (double(width) * height));
    m.directions = TexelDirections(width, height);
    for (float v : m.importance) m.total += v;
    return m;
}

// Cells as columns: texel (i, j) in column_cell[i].
std::vector<std::uint16_t> column_cells(int width, int height, const std::vector<int>& column_cell) {
    std::vector<std::uint16_t> cells(size_t(width) * size_t(height));
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i)
            cells[size_t(j) * size_t(width) + size_t(i)] = std::uint16_t(column_cell[size_t(i)]);
    return cells;
}

std::vector<double> cell_masses(const ImportanceMap& m, const std::vector<std::uint16_t>& cells, int count) {
    std::vector<double> mass(size_t(count), 0.0);
    for (size_t t = 0; t < cells.size(); ++t) mass[cells[t]] += m.importance[t];
    return mass;
}

// Whether every cell's texels are one 4-connected region, columns wrapping around the seam.
bool cells_connected(int width, int height, const std::vector<std::uint16_t>& cells, int count) {
    std::vector<bool> seen(cells.size(), false), started(size_t(count), false);
    for (size_t start = 0; start < cells.size(); ++start) {
        if (seen[start]) continue;
        if (started[cells[start]]) return false;  // a second region of a cell
        started[cells[start]] = true;
        std::vector<size_t> stack{start};
        seen[start] = true;
        while (!stack.empty()) {
            const size_t t = stack.back();
            stack.pop_back();
            const int i = int(t % size_t(width)), j = int(t / size_t(width));
            for (const auto& [i2, j2] : {std::pair{(i + 1) % width, j}, std::pair{(i + width - 1) % width, j},
                                         std::pair{i, j + 1}, std::pair{i, j - 1}}) {
                if (j2 < 0 || j2 >= height) continue;
                const size_t q = size_t(j2) * size_t(width) + size_t(i2);
                if (!seen[q] && cells[q] == cells[t]) {
                    seen[q] = true;
                    stack.push_back(q);
                }
            }
        }
    }
    return true;
}

// Two cells of equal texels, 96 and 32 of them (the small one across the seam): whole texels move
// until they hold 64 each, and both stay one region.
TEST(BalanceTexels, TwoCellsEndWithinOneTexelOfEqual) {
    const int w = 16, h = 8;
    const ImportanceMap m = synthetic_importance(w, h, std::vector<float>(size_t(w * h), 1.0f));
    std::vector<std::uint16_t> cells = column_cells(w, h, {1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1});
    ASSERT_EQ(cell_masses(m, cells, 2), (std::vector<double>{96.0, 32.0}));
    const TexelBalance b = balance_texels(m, cells, 2);
    const std::vector<double> mass = cell_masses(m, cells, 2);
    EXPECT_LE(std::abs(mass[0] - mass[1]), 1.0) << mass[0] << " vs " << mass[1];
    EXPECT_EQ(b.moves, 32u);  // each move narrows the gap by two texels
    EXPECT_LT(b.passes, kCcvtBalancePasses);
    EXPECT_TRUE(cells_connected(w, h, cells, 2));
}

// Uneven texels in eight column strips of uneven widths: neighbouring cells end within the heaviest
// texel of each other, every cell keeps texels and stays one region, and the same input gives the same
// cells.
TEST(BalanceTexels, UnevenTexelsEndWithinATexelOfTheirNeighbours) {
    const int w = 64, h = 32, count = 8;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<float> weight(0.5f, 1.5f);
    std::vector<float> weights(size_t(w * h));
    for (float& v : weights) v = weight(rng);
    const ImportanceMap m = synthetic_importance(w, h, weights);
    std::vector<int> column;
    for (const auto& [cell, columns] : {std::pair{0, 16}, std::pair{1, 8}, std::pair{2, 4}, std::pair{3, 12},
                                        std::pair{4, 6}, std::pair{5, 10}, std::pair{6, 2}, std::pair{7, 6}})
        column.insert(column.end(), size_t(columns), cell);
    std::vector<std::uint16_t> cells = column_cells(w, h, column), again = cells;
    const double share = m.total / count;
    auto deviation = [&](const std::vector<double>& mass) {
        double sum = 0.0;
        for (double x : mass) sum += (x - share) * (x - share);
        return std::sqrt(sum / count) / share;
    };
    const double before = deviation(cell_masses(m, cells, count));
    balance_texels(m, cells, count);
    balance_texels(m, again, count);
    EXPECT_EQ(cells, again);
    const std::vector<double> mass = cell_masses(m, cells, count);
    EXPECT_GT(before, 0.5);
    EXPECT_LT(deviation(mass), 0.05) << "from " << before;  // neighbours within kCcvtBalanceTolerance each
    for (int k = 0; k < count; ++k) {
        EXPECT_GT(mass[size_t(k)], 0.0);
        const int next = (k + 1) % count;  // strips: k borders k + 1 (and 7 borders 0 across the seam)
        EXPECT_LE(std::abs(mass[size_t(k)] - mass[size_t(next)]), std::max(1.5, kCcvtBalanceTolerance * share))
            << "cells " << k << " and " << next;
    }
    EXPECT_TRUE(cells_connected(w, h, cells, count));
}

// A sun (a texel heavier than a share) is left out of the sharing: its cell takes the same share of the
// rest as the others instead of shedding everything around the sun, and the sun itself stays put.
TEST(BalanceTexels, SunTexelsAreLeftOutOfTheSharing) {
    const int w = 32, h = 16, count = 8;
    std::vector<float> weights(size_t(w * h), 1.0f);
    const size_t sun = size_t(5) * size_t(w) + 3;
    weights[sun] = 200.0f;
    const ImportanceMap full = synthetic_importance(w, h, weights);
    const ImportanceMap shared = shareable_importance(full, count);
    ASSERT_EQ(shared.importance[sun], 0.0f);
    std::vector<int> column;
    for (const auto& [cell, columns] : {std::pair{0, 8}, std::pair{1, 2}, std::pair{2, 6}, std::pair{3, 4},
                                        std::pair{4, 4}, std::pair{5, 2}, std::pair{6, 2}, std::pair{7, 4}})
        column.insert(column.end(), size_t(columns), cell);
    std::vector<std::uint16_t> cells = column_cells(w, h, column);
    balance_texels(shared, cells, count);
    EXPECT_EQ(cells[sun], 0);
    const std::vector<double> mass = cell_masses(shared, cells, count);  // without the sun
    for (int k = 0; k < count; ++k) EXPECT_NEAR(mass[size_t(k)], shared.total / count, 1.5) << "cell " << k;
    EXPECT_TRUE(cells_connected(w, h, cells, count));
}

// Spearman rank correlation.
double rank_correlation(const std::vector<double>& a, const std::vector<double>& b) {
    auto ranks = [](const std::vector<double>& v) {
        std::vector<size_t> order(v.size());
        for (size_t k = 0; k < v.size(); ++k) order[k] = k;
        std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return v[x] < v[y]; });
        std::vector<double> r(v.size());
        for (size_t k = 0; k < order.size(); ++k) r[order[k]] = double(k);
        return r;
    };
    const std::vector<double> ra = ranks(a), rb = ranks(b);
    const double mean = (double(a.size()) - 1.0) / 2.0;
    double num = 0.0, da = 0.0, db = 0.0;
    for (size_t k = 0; k < a.size(); ++k) {
        num += (ra[k] - mean) * (rb[k] - mean);
        da += (ra[k] - mean) * (ra[k] - mean);
        db += (rb[k] - mean) * (rb[k] - mean);
    }
    return num / std::sqrt(da * db);
}

TEST(Lloyd, PlacesSmallerCellsWhereImportanceIsHigher) {
    for (const std::string name : {"sunrise", "courtyard", "night"}) {
        const EnvironmentMap& map = test::world(name);
        const Decomposition d = run(map, Method::lloyd, 64);
        const ImportanceMap importance = build_importance(map);
        std::vector<double> mass(d.cells.size(), 0.0), density, area;
        for (size_t t = 0; t < importance.texel_count(); ++t) mass[d.texel_cell[t]] += importance.importance[t];
        for (size_t k = 0; k < d.cells.size(); ++k) {
            density.push_back(mass[k] / d.cells[k].solid_angle);
            area.push_back(d.cells[k].solid_angle);
        }
        EXPECT_LT(rank_correlation(density, area), -0.6) << name;
        EXPECT_GT(d.coarse_iterations, 1) << name << ": no coarse stage";
        EXPECT_GT(d.iterations, d.coarse_iterations) << name;
        EXPECT_LT(d.iterations - d.coarse_iterations, kLloydMaxIterations) << name << ": did not converge";
    }
}

// Lloyd lands in minima of about the same quality whatever the seed. The quantisation
// energy sum I (1 - w . c) of the cells (recomputed here from the map's texels and the cells' centres)
// over seeds 1-8, upper hemisphere, N = 128: measured spread 2.4% (courtyard) and 1.6% (studio).
TEST(Lloyd, SeedsGiveMinimaOfTheSameEnergyOnTheUpperHemisphere) {
    for (const std::string name : {"courtyard", "studio"}) {
        const EnvironmentMap& map = test::world(name);
        double lowest = 1e300, highest = 0.0;
        for (std::uint64_t seed = 1; seed <= 8; ++seed) {
            DecomposeOptions options;
            options.lights = 128;
            options.seed = seed;
            options.hemisphere = Hemisphere::upper;
            const Decomposition d = decompose(map, options);
            double energy = 0.0;
            for (int j = 0; j < map.height / 2; ++j) {
                const double dw = latlong::texel_solid_angle(j, map.width, map.height);
                for (int i = 0; i < map.width; ++i) {
                    const Cell& cell = d.cells[d.texel_cell[size_t(j) * size_t(map.width) + size_t(i)]];
                    energy += latlong::luminance(glm::dvec3(map.at(i, j))) * dw *
                              (1.0 - glm::dot(latlong::texel_direction(i, j, map.width, map.height),
                                              glm::dvec3(cell.direction)));
                }
            }
            lowest = std::min(lowest, energy);
            highest = std::max(highest, energy);
        }
        EXPECT_LT(highest, 1.05 * lowest) << name << ": energies from " << lowest << " to " << highest;
    }
}

// Over-relaxed steps (docs/DESIGN.md §3): on the eight maps, N = 128, fewer iterations than
// Lloyd's own steps (measured: 367 against 576 in all) to an energy sum I (1 - w . s) as low (measured: within
// 0.6% either way on every map, 0.2% lower on average).
TEST(Lloyd, OverRelaxedStepsConvergeInFewerIterationsToAnEnergyAsLow) {
    auto energy = [](const ImportanceMap& importance, const SiteSet& sites) {
        std::vector<std::uint16_t> texel_cell(importance.texel_count());
        assign_nearest_brute_force(importance, sites.sites, {}, texel_cell);
        double e = 0.0;
        for (int j = 0; j < importance.height; ++j)
            for (int i = 0; i < importance.width; ++i) {
                const size_t t = size_t(j) * size_t(importance.width) + size_t(i);
                e += importance.importance[t] *
                     (1.0 - glm::dot(importance.directions(i, j), sites.sites[texel_cell[t]]));
            }
        return e;
    };
    int plain_iterations = 0, over_iterations = 0;
    for (const std::string& name : test::kWorldNames) {
        const ImportanceMap importance = build_importance(test::world(name));
        const Partition partition(importance, SiteSearch::tiles);
        const SiteSet plain = sites_lloyd(importance, 128, 1, partition, 1.0);
        const SiteSet over = sites_lloyd(importance, 128, 1, partition, kLloydOverRelaxation);
        plain_iterations += plain.iterations;
        over_iterations += over.iterations;
        EXPECT_LT(energy(importance, over), 1.01 * energy(importance, plain)) << name;
    }
    EXPECT_LT(over_iterations, 0.8 * plain_iterations) << over_iterations << " against " << plain_iterations;
}

TEST(FloydSteinberg, GivesTheAskedNumberOfSamplesToWithinTwo) {
    for (const std::string& name : test::kWorldNames)
        for (int lights : {1, 2, 3, 16, 100, 256}) {
            const ImportanceMap importance = build_importance(test::world(name));
            const int samples = int(sites_floyd_steinberg(importance, lights).sites.size());
            EXPECT_LE(std::abs(samples - lights), 2) << name << " N=" << lights;
        }
}

TEST(MedianCut, GivesAPowerOfTwoCellsOfNearlyEqualImportance) {
    const EnvironmentMap& map = test::world("courtyard");
    for (const auto& [lights, cells] : {std::pair{1, 1}, std::pair{100, 64}, std::pair{128, 128}, std::pair{255, 128}})
        EXPECT_EQ(int(run(map, Method::mediancut, lights).cells.size()), cells);
}

TEST(Random, DrawsTexelsInProportionToImportance) {
    // One draw per seed: the sun texel of city holds 6.7% of the importance.
    const ImportanceMap importance = build_importance(test::world("city"));
    const size_t sun = size_t(std::max_element(importance.importance.begin(), importance.importance.end()) -
                              importance.importance.begin());
    const double share = importance.importance[sun] / importance.total;
    int hits = 0;
    const int draws = 1000;
    for (int seed = 0; seed < draws; ++seed) {
        std::mt19937_64 rng(std::uint64_t(seed) * 7919u + 1u);
        hits += sample_distinct_texels(importance, 1, rng).front() == sun;
    }
    const double sigma = std::sqrt(share * (1.0 - share) / draws);
    EXPECT_NEAR(double(hits) / draws, share, 4.0 * sigma);
}

TEST(Decompose, TinyAndBlackMapsGiveWellDefinedCells) {
    EnvironmentMap tiny;
    tiny.width = 2;
    tiny.height = 1;
    tiny.texels = {glm::vec3(1.0f, 2.0f, 3.0f), glm::vec3(0.5f)};
    tiny.source = "tiny";
    for (Method method : enum_values<Method>())
        for (int lights : {1, 2}) {
            const Decomposition d = run(tiny, method, lights);
            expect_valid(tiny, d, test::direct_integral(tiny), method, lights,
                         "tiny " + std::string(to_string(method)));
        }
    EXPECT_THROW(run(tiny, Method::lloyd, 3), InputError);

    const EnvironmentMap black = load_environment("builtin:constant:0");
    for (Method method : enum_values<Method>()) {
        const Decomposition d = run(black, method, 16);
        EXPECT_TRUE(d.uniform_importance);
        expect_valid(black, d, glm::dvec3(0.0), method, 16, "black " + std::string(to_string(method)));
        for (const Cell& c : d.cells) EXPECT_GT(c.solid_angle, 0.0f) << to_string(method);
    }
}

TEST(Decompose, RejectsLightCountsOutsideTheRange) {
    const EnvironmentMap map = load_environment("builtin:constant");
    EXPECT_THROW(run(map, Method::lloyd, 0), UsageError);
    EXPECT_THROW(run(map, Method::lloyd, 257), UsageError);
    EXPECT_THROW(parse_enum<Method>("kmeans"), UsageError);
    for (Method method : enum_values<Method>()) EXPECT_EQ(parse_enum<Method>(to_string(method)), method);
}

TEST(CellOverlay, DrawsBordersAndCentresOverTheMap) {
    const EnvironmentMap& map = test::world("city");
    const Decomposition d = run(map, Method::mediancut, 16);
    const Image8 picture = draw_cells(map, d);
    ASSERT_EQ(picture.width, map.width);
    ASSERT_EQ(picture.height, map.height);
    for (const Cell& c : d.cells) {
        const glm::dvec2 uv = latlong::uv(glm::dvec3(c.direction));
        const std::uint8_t* p =
            picture.at(int(uv.x * map.width) % map.width, std::min(map.height - 1, int(uv.y * map.height)));
        EXPECT_EQ(p[0], 255);
        EXPECT_EQ(p[1], 40);
    }
    // Borders wherever two neighbouring texels belong to different cells.
    int borders = 0;
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i + 1 < map.width; ++i)
            if (d.texel_cell[size_t(j) * size_t(map.width) + size_t(i)] !=
                d.texel_cell[size_t(j) * size_t(map.width) + size_t(i) + 1]) {
                const std::uint8_t* p = picture.at(i, j);
                borders += (p[0] == 255 && p[1] == 255 && p[2] == 255) || (p[0] == 255 && p[1] == 40) || p[0] == 0;
            }
    EXPECT_GT(borders, 0);
}

}  // namespace
}  // namespace envshadow
