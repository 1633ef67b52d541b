// Lloyd relaxation on the sphere (sites_lloyd, env/sites.h).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <queue>
#include <unordered_map>

#include "env/latlong.h"
#include "env/relaxation.h"
#include "env/sites.h"

namespace envshadow {
namespace {

using namespace relaxation;  // what Lloyd and CCVT share (env/relaxation.h)

// Moves every site along the great circle towards its cell's centroid, `reach` times the angle to it
// (1: onto the centroid, Lloyd's step; above 1: over-relaxed, past it); returns the largest movement
// (radians).
double move_towards_centroids(std::vector<glm::dvec3>& sites, const std::vector<CellMoments>& cells, double reach) {
    double movement = 0.0;
    for (size_t k = 0; k < sites.size(); ++k) {
        const glm::dvec3 s = sites[k];
        const glm::dvec3 c = centroid_direction(cells[k], s);
        const double angle = angle_between(c, s);
        if (!(angle > 0.0)) continue;
        if (reach == 1.0) {
            sites[k] = c;
        } else {
            const glm::dvec3 axis = glm::normalize(c - s * glm::dot(c, s));
            sites[k] = glm::normalize(s * std::cos(reach * angle) + axis * std::sin(reach * angle));
        }
        movement = std::max(movement, reach * angle);
    }
    return movement;
}

// Floyd-Steinberg samples of `weight`, the seed shifting the halftoning's starting error; one short
// (the halftoning may give M - 1) is made up at the heaviest texel no sample stands on.
std::vector<glm::dvec3> initial_sites(const ImportanceMap& importance, std::span<const float> weight, int count,
                                      std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<glm::dvec3> sites = floyd_steinberg_samples(importance, weight, count, 2.0 * uniform01(rng) - 1.0);
    if (int(sites.size()) < count) {
        std::vector<bool> taken(importance.texel_count(), false);
        for (const glm::dvec3& s : sites) {
            const glm::dvec2 uv = latlong::uv(s);
            const int i = std::min(importance.width - 1, int(uv.x * importance.width));
            const int j = std::min(importance.height - 1, int(uv.y * importance.lat_long_height()));
            taken[size_t(j) * size_t(importance.width) + size_t(i)] = true;
        }
        std::vector<std::size_t> order(importance.texel_count());
        for (std::size_t t = 0; t < order.size(); ++t) order[t] = t;
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return weight[a] > weight[b]; });
        for (std::size_t t : order) {
            if (int(sites.size()) >= count) break;
            if (!taken[t]) sites.push_back(texel_centres(importance, std::span(&t, 1)).front());
        }
    }
    return sites;
}

// Sum over cells of sum I (1 - w . s): the quantisation energy Lloyd's iteration decreases.
double lloyd_energy(const std::vector<glm::dvec3>& sites, const std::vector<CellMoments>& cells) {
    double energy = 0.0;
    for (size_t k = 0; k < sites.size(); ++k)
        energy += cells[k].importance - glm::dot(cells[k].importance_direction, sites[k]);
    return energy;
}

// Lloyd iterations from result.sites until an iteration gains less than kLloydEnergyTolerance of the
// energy; adds the iterations run to result.iterations. Each step moves a site `over_relaxation` times the
// way to its centroid (over-relaxation, 1 <= w < 2; 1.9 takes about half the iterations of Lloyd's w = 1 to an
// energy as low, docs/PERFORMANCE.md): a step that raises the energy is taken back and replaced by Lloyd's own step
// from the same sites, which never raises it, so the energy falls at every accepted iteration as in plain Lloyd.
void relax_lloyd(const Partition& partition, double over_relaxation, SiteSet& result) {
    double previous_energy = std::numeric_limits<double>::infinity();
    std::vector<glm::dvec3> previous_sites;
    std::vector<CellMoments> previous_cells;
    double reach = 1.0;  // of the step that led here
    for (int iteration = 1; iteration <= kLloydMaxIterations; ++iteration) {
        std::vector<CellMoments> cells = partition.moments(result.sites, {});
        const double energy = lloyd_energy(result.sites, cells);
        ++result.iterations;
        if (energy > previous_energy && reach > 1.0) {  // overshot: Lloyd's step from where this one began
            result.sites = std::move(previous_sites);
            cells = std::move(previous_cells);
            reach = 1.0;
        } else {
            // Converged: the last move gained less than kLloydEnergyTolerance of the energy. The sites stay
            // where this partition was computed; final_movement is how far the next step would move them.
            if (previous_energy - energy <= kLloydEnergyTolerance * energy) {
                result.final_movement = 0.0;
                for (size_t k = 0; k < result.sites.size(); ++k)
                    result.final_movement =
                        std::max(result.final_movement,
                                 angle_between(centroid_direction(cells[k], result.sites[k]), result.sites[k]));
                return;
            }
            previous_energy = energy;
            reach = over_relaxation;
        }
        previous_sites = result.sites;
        previous_cells = cells;
        result.final_movement = move_towards_centroids(result.sites, cells, reach);
        result.final_movement = std::max(result.final_movement, reseed_empty_cells(result.sites, nullptr, cells));
        if (result.final_movement == 0.0) return;
    }
}

}  // namespace

SiteSet sites_lloyd(const ImportanceMap& importance, int count, std::uint64_t seed, const Partition& partition,
                    double over_relaxation) {
    // Start at Lloyd's asymptotic site density, sqrt of the importance density (Gersho 1979: rho^(d/(d+2))
    // in d = 2 dimensions), well stratified: weight sqrt(lum) dw = sqrt(I dw). (The weights are freed
    // before the coarse stage allocates.)
    SiteSet result;
    {
        std::vector<float> weight(importance.texel_count());
        for (int j = 0; j < importance.height; ++j)
            for (int i = 0; i < importance.width; ++i) {
                const size_t t = size_t(j) * size_t(importance.width) + size_t(i);
                weight[t] = float(std::sqrt(double(importance.importance[t]) * importance.row_solid_angle[size_t(j)]));
            }
        result.sites = initial_sites(importance, weight, count, seed);
    }
    // Coarse to fine: converged at a lower resolution, where an iteration costs a fraction, the sites
    // need few iterations more at full resolution.
    for (int factor : kLloydCoarseFactors) {
        if (!coarsens(importance, factor)) continue;
        const Resolution coarse = at_resolution(importance, factor, 0, partition.search());
        relax_lloyd(*coarse.partition, over_relaxation, result);
    }
    result.coarse_iterations = result.iterations;
    relax_lloyd(partition, over_relaxation, result);
    return result;
}

}  // namespace envshadow
