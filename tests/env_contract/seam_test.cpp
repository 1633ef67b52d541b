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

// Turning the map 180° about +Y (columns rolled by W/2) moves the wrap to the middle. The cells' radiance
// distribution must not change more than a change of seed changes it (the roll moves only where the
// initial sites fall, as the seed does) plus 5% of the energy: a sun split at the wrap moves a third.
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
                EXPECT_TRUE(area[k] > 0.75 * m && area[k] < 1.33 * m) << context << ": cell " << k << " has " << area[k] / m
                                                                      << " of the mean solid angle";
            const std::size_t north = d.texel_cell[0], south = d.texel_cell[texel_index(0, map.height - 1, map.width)];
            EXPECT_GT(area[north], 0.75 * m) << context << ": the cell at the zenith";
            EXPECT_GT(area[south], 0.75 * m) << context << ": the cell at the nadir";
        }
}

}  // namespace
}  // namespace envshadow::contract
