// No seam and no pole artefacts, as properties: the u = 0/1 wrap is an ordinary place on the sphere,
// turning the map about +Y changes nothing that matters, and the poles' tiny texels do not make tiny cells.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "contract_helpers.h"

namespace envshadow::contract {
namespace {

// The wrap column pair (W-1, 0) against the W-1 interior pairs (i, i+1): in how many rows do the two
// columns' cells differ? A method that splits cells at the wrap crosses there in (nearly) every row; a
// seam-blind one makes the wrap an ordinary pair, its rank among all pairs uniform in [0, 1]. So: per
// decomposition the wrap is crossed no more than the most-crossed interior pair, and per method over the
// 16 decompositions (8 maps, N = 16 and 128) its mean rank stays under 0.8 (uniform ranks average
// 0.5 ± 0.07). CCVT takes seconds per map: four quick decompositions, the first rule only.
TEST(EnvContractSeam, WrapColumnsAreNoMoreACellBorderThanOtherColumns) {
    for (Method method : kAllMethods) {
        double rank_sum = 0.0;
        int decompositions = 0;
        for (const char* name : kBlenderMaps) {
            const std::string spec = blender_map(name);
            const bool quick = spec.find("courtyard") != std::string::npos || spec.find("city") != std::string::npos;
            if (method == Method::ccvt && !quick) continue;
            for (int lights : {16, method == Method::ccvt ? 64 : 128}) {
                const Decomposition d = decompose(cached_map(spec), {.method = method, .lights = lights});
                const int wrap = column_pair_crossings(d, d.width - 1, 0);
                int most = 0, below = 0, equal = 0;
                for (int i = 0; i + 1 < d.width; ++i) {
                    const int c = column_pair_crossings(d, i, i + 1);
                    most = std::max(most, c);
                    below += c < wrap;
                    equal += c == wrap;
                }
                EXPECT_LE(wrap, most) << describe(spec, method, lights) << ": the wrap is crossed in " << wrap << " of "
                                      << d.height << " rows";
                rank_sum += (below + 0.5 * equal) / double(d.width - 1);
                ++decompositions;
            }
        }
        if (method != Method::ccvt) {
            EXPECT_LT(rank_sum / decompositions, 0.8)
                << to_string(method) << ": over " << decompositions
                << " decompositions the wrap ranks, on average, above this share of the interior column pairs";
        }
    }
}

// The sun of builtin:sky at azimuth 0 straddles the wrap; at azimuth 180 the same picture sits in the middle
// of the map (the two maps are each other's columns rolled by W/2). Where a method keeps the sun's
// straddling texels in one cell in the middle, it must keep them together on the wrap too. Lloyd at N = 16
// keeps the sun whole; CCVT is left out: it gives the sun (two thirds of the integral) about two thirds of
// the cells, so never keeps it whole, and takes seconds per sky.
TEST(EnvContractSeam, SunOnTheWrapIsNotSplitThere) {
    const EnvironmentMap& wrap_map = cached_map("builtin:sky:azimuth=0,elevation=20");
    const EnvironmentMap& middle_map = cached_map("builtin:sky:azimuth=180,elevation=20");
    const std::vector<double> importance = texel_importance(wrap_map);
    double total = 0.0;
    for (double v : importance) total += v;
    const int w = wrap_map.width;
    // Rows where the disc covers both columns next to the wrap (the same rows hold it at W/2 - 1, W/2).
    std::vector<int> sun_rows;
    for (int j = 0; j < wrap_map.height; ++j)
        if (importance[texel_index(0, j, w)] > 1e-4 * total && importance[texel_index(w - 1, j, w)] > 1e-4 * total)
            sun_rows.push_back(j);
    ASSERT_GE(sun_rows.size(), 2u) << "the disc should straddle the wrap";

    auto sun_whole = [&](const Decomposition& d, int a, int b) {
        for (int j : sun_rows)
            if (d.texel_cell[texel_index(a, j, w)] != d.texel_cell[texel_index(b, j, w)]) return false;
        return true;
    };
    int exercised = 0;
    for (Method method : {Method::lloyd, Method::mediancut, Method::random, Method::fs})
        for (std::uint64_t seed = 1; seed <= (method == Method::lloyd ? 4u : 1u); ++seed) {
            const DecomposeOptions options{.method = method, .lights = 16, .seed = seed};
            const bool whole_in_middle = sun_whole(decompose(middle_map, options), w / 2 - 1, w / 2);
            exercised += whole_in_middle;
            if (whole_in_middle) {
                EXPECT_TRUE(sun_whole(decompose(wrap_map, options), w - 1, 0))
                    << to_string(method) << " seed " << seed
                    << ": the sun is one cell in the middle of the map but split at the wrap";
            }
        }
    EXPECT_GE(exercised, 4) << "the sun should be one cell in the middle for Lloyd's four seeds at least";
}

// Sorted cell luminances as cumulative shares of the total: the radiance distribution of the cells.
std::vector<double> cumulative_shares(const Decomposition& d) {
    std::vector<double> lum;
    for (const Cell& c : d.cells) lum.push_back(latlong::luminance(glm::dvec3(c.radiance)));
    std::sort(lum.rbegin(), lum.rend());
    double total = 0.0;
    for (double v : lum) total += v;
    double running = 0.0;
    for (double& v : lum) v = (running += v) / total;
    return lum;
}

// Largest difference between two cumulative distributions (a Kolmogorov-Smirnov distance over the sorted
// cells): the share of the energy that would have to move between cells to turn one into the other.
double distribution_distance(const Decomposition& a, const Decomposition& b) {
    const std::vector<double> x = cumulative_shares(a), y = cumulative_shares(b);
    double largest = 0.0;
    for (std::size_t k = 0; k < std::max(x.size(), y.size()); ++k)
        largest = std::max(largest, std::abs(x[std::min(k, x.size() - 1)] - y[std::min(k, y.size() - 1)]));
    return largest;
}

// Turning the map 180° about +Y (columns rolled by W/2) moves the wrap to the middle. The cells' radiance
// distribution must not change more than a change of seed changes it (the roll moves only where the
// initial sites fall, as the seed does) plus 5% of the energy: a sun split at the wrap moves a third.
TEST(EnvContractSeam, RolledMapHasTheSameCellRadianceDistribution) {
    for (const std::string& spec : {blender_map("courtyard"), blender_map("city"), blender_map("sunrise"),
                                    std::string("builtin:sky:azimuth=0,elevation=20")}) {
        const EnvironmentMap& map = cached_map(spec);
        const EnvironmentMap rolled = rolled_half_turn(map);
        for (Method method : {Method::lloyd, Method::ccvt}) {
            // CCVT takes many seconds on maps with a sun: city at N = 16 only (the sky is SunOnTheWrap's).
            const bool sun = spec.find("courtyard") == std::string::npos;
            if (method == Method::ccvt && sun && spec.find("city") == std::string::npos) continue;
            const int lights = method == Method::ccvt && sun ? 16 : 64;
            const Decomposition a = decompose(map, {.method = method, .lights = lights, .seed = 1});
            const Decomposition r = decompose(rolled, {.method = method, .lights = lights, .seed = 1});
            double seed_spread = 0.0;
            if (method == Method::lloyd) {
                const Decomposition b = decompose(map, {.method = method, .lights = lights, .seed = 2});
                const Decomposition c = decompose(map, {.method = method, .lights = lights, .seed = 3});
                seed_spread =
                    std::max({distribution_distance(a, b), distribution_distance(a, c), distribution_distance(b, c)});
            }
            EXPECT_LE(distribution_distance(a, r), seed_spread + 0.05)
                << describe(spec, method, lights) << ": seeds differ by " << seed_spread;
        }
    }
}

// On a uniform sphere Lloyd's and CCVT's cells are all alike (a centroidal Voronoi tessellation has cells
// of nearly equal area); lat-long texels shrink towards the poles, so a missing dω weight or a pole
// singularity shows up as small (or huge) cells there.
TEST(EnvContractPoles, UniformSphereGivesCellsOfEqualSolidAngle) {
    const EnvironmentMap& map = cached_map("builtin:constant");
    const std::vector<double> importance = texel_importance(map);
    for (Method method : {Method::lloyd, Method::ccvt})
        for (int lights : {16, 64, 128}) {
            const std::string context = describe("builtin:constant", method, lights);
            const Decomposition d = decompose(map, {.method = method, .lights = lights});
            const std::vector<double> area = cell_sums(map, importance, d.texel_cell, d.cells.size()).solid_angle;
            const double m = mean(area);
            EXPECT_LT(coefficient_of_variation(area), 0.1) << context;
            for (std::size_t k = 0; k < area.size(); ++k)
                EXPECT_TRUE(area[k] > 0.75 * m && area[k] < 1.33 * m)
                    << context << ": cell " << k << " has " << area[k] / m << " of the mean solid angle";
            const std::size_t north = d.texel_cell[0], south = d.texel_cell[texel_index(0, map.height - 1, map.width)];
            EXPECT_GT(area[north], 0.75 * m) << context << ": the cell at the zenith";
            EXPECT_GT(area[south], 0.75 * m) << context << ": the cell at the nadir";
        }
}

}  // namespace
}  // namespace envshadow::contract
