#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <string>

#include "core/error.h"
#include "env/cells.h"
#include "env/nearest_site.h"
#include "env/sites.h"

namespace envshadow {

std::vector<Cell> integrate_cells(const EnvironmentMap& map, const ImportanceMap& importance,
                                  std::span<const std::uint16_t> texel_cell, std::span<const glm::dvec3> sites) {
    const int count = int(sites.size());
    const std::vector<CellMoments> moments = partition_moments(importance, texel_cell, count);

    // Radiance per cell: rows in fixed chunks, reduced in order (independent of the thread count).
    constexpr int kRowsPerChunk = 8;
    const int rows = importance.height;
    const int chunks = (rows + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<std::vector<glm::dvec3>> partial(static_cast<size_t>(chunks),
                                                 std::vector<glm::dvec3>(static_cast<size_t>(count), glm::dvec3(0.0)));
    tbb::parallel_for(0, chunks, [&](int chunk) {
        for (int j = chunk * kRowsPerChunk; j < std::min(rows, (chunk + 1) * kRowsPerChunk); ++j) {
            const double dw = importance.row_solid_angle[size_t(j)];
            for (int i = 0; i < map.width; ++i)
                partial[size_t(chunk)][texel_cell[size_t(j) * size_t(map.width) + size_t(i)]] +=
                    dw * glm::dvec3(map.at(i, j));
        }
    });
    std::vector<Cell> cells(static_cast<size_t>(count));
    for (int k = 0; k < count; ++k) {
        glm::dvec3 radiance(0.0);
        for (const auto& p : partial) radiance += p[size_t(k)];
        const CellMoments& m = moments[size_t(k)];
        const glm::dvec3 centre = centroid_direction(m, sites[size_t(k)]);
        // Mean cosine about the centre, importance weighted (solid-angle weighted without importance):
        // sum I (w . c) = c . sum I w.
        double mean_cos = 1.0;
        if (m.importance > 0.0)
            mean_cos = glm::dot(centre, m.importance_direction) / m.importance;
        else if (m.solid_angle > 0.0)
            mean_cos = glm::dot(centre, m.solid_angle_direction) / m.solid_angle;
        Cell& cell = cells[size_t(k)];
        cell.direction = glm::vec3(centre);
        cell.radiance = glm::vec3(radiance);
        cell.solid_angle = float(m.solid_angle);
        cell.cos_radius = float(std::clamp(1.0 - m.solid_angle / (2.0 * std::numbers::pi), -1.0, 1.0));
        cell.cos_radius_weighted = float(std::clamp(2.0 * mean_cos - 1.0, -1.0, 1.0));
    }
    return cells;
}

Decomposition decompose(const EnvironmentMap& map, const DecomposeOptions& options) {
    if (options.lights < 1 || options.lights > kMaxLights)
        throw UsageError("a decomposition into " + std::to_string(options.lights) + " cells: the count must be 1.." +
                         std::to_string(kMaxLights));
    const long long texels = (long long)map.width * hemisphere_rows(map.height, options.hemisphere);
    if (texels < options.lights)
        throw InputError(map.source + ": a " + std::to_string(map.width) + "x" + std::to_string(map.height) +
                         " map has " +
                         (options.hemisphere == Hemisphere::upper ? "fewer texels above the horizon" : "fewer texels") +
                         " than the " + std::to_string(options.lights) + " lights asked for");
    const auto start = std::chrono::steady_clock::now();

    const ImportanceMap importance = build_importance(map, options.hemisphere);
    const Partition partition(importance, options.search);

    SiteSet sites;
    switch (options.method) {
        case Method::lloyd:
            sites = sites_lloyd(importance, options.lights, options.seed, partition);
            break;
        case Method::ccvt:
            sites = sites_ccvt(importance, options.lights, partition);
            break;
        case Method::mediancut:
            sites = sites_median_cut(importance, options.lights);
            break;
        case Method::random:
            sites = sites_random(importance, options.lights, options.seed);
            break;
        case Method::fs:
            sites = sites_floyd_steinberg(importance, options.lights);
            break;
    }

    Decomposition result;
    result.method = options.method;
    result.hemisphere = options.hemisphere;
    result.width = map.width;
    result.height = map.height;
    if (sites.texel_cell.size() == importance.texel_count()) {
        result.texel_cell = std::move(sites.texel_cell);  // CCVT's balanced power cells
    } else {
        result.texel_cell.resize(importance.texel_count());
        partition.assign(sites.sites, sites.bias, result.texel_cell);
        fill_empty_cells(importance, partition, sites.sites, sites.bias, result.texel_cell);
    }
    result.cells = integrate_cells(map, importance, result.texel_cell, sites.sites);
    result.texel_cell.resize(map.texels.size(), kNoCell);  // the rows below the horizon: no cell
    result.integral = integrate_radiance(map, options.hemisphere);
    result.iterations = sites.iterations;
    result.coarse_iterations = sites.coarse_iterations;
    result.final_movement = sites.final_movement;
    result.sites = std::move(sites.sites);
    result.site_bias = std::move(sites.bias);
    result.uniform_importance = importance.uniform_fallback;
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace envshadow
