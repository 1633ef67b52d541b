#include "env/compact_sources.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include <glm/geometric.hpp>

#include "env/latlong.h"

namespace envshadow {

namespace {

struct Region {
    std::vector<std::size_t> texels;
    glm::dvec3 radiance{0.0};       // L dw
    glm::dvec3 moment{0.0};         // luminance dw times the direction
    glm::dvec3 excess_moment{0.0};  // the same of the excess over the threshold
    double excess_luminance = 0.0;  // excess luminance dw
};

}  // namespace

CompactSourceSplit split_compact_sources(const EnvironmentMap& map, Hemisphere hemisphere) {
    CompactSourceSplit split{map, {}};
    const int width = map.width, rows = hemisphere_rows(map.height, hemisphere);
    double luminance_integral = 0.0, solid_angle = 0.0;
    for (int j = 0; j < rows; ++j) {
        const double dw = hemisphere_texel_solid_angle(j, width, map.height, hemisphere);
        for (int i = 0; i < width; ++i) luminance_integral += dw * latlong::luminance(glm::dvec3(map.at(i, j)));
        solid_angle += dw * width;
    }
    if (!(luminance_integral > 0.0) || !(solid_angle > 0.0)) return split;
    const double threshold = kCompactRadianceFactor * luminance_integral / solid_angle;
    const auto index = [width](int i, int j) { return std::size_t(j) * std::size_t(width) + std::size_t(i); };
    const auto above = [&](int i, int j) { return latlong::luminance(glm::dvec3(map.at(i, j))) > threshold; };

    // 4-connected regions above the threshold, u wrapping, by a flood fill from each unvisited texel.
    std::vector<std::uint8_t> visited(std::size_t(width) * std::size_t(rows), 0);
    std::vector<Region> regions;
    std::vector<std::pair<int, int>> stack;
    for (int j0 = 0; j0 < rows; ++j0) {
        for (int i0 = 0; i0 < width; ++i0) {
            if (visited[index(i0, j0)] || !above(i0, j0)) continue;
            Region& region = regions.emplace_back();
            visited[index(i0, j0)] = 1;
            stack.assign(1, {i0, j0});
            while (!stack.empty()) {
                const auto [i, j] = stack.back();
                stack.pop_back();
                region.texels.push_back(index(i, j));
                const glm::dvec3 radiance(map.at(i, j));
                const double luminance = latlong::luminance(radiance);
                const double dw = hemisphere_texel_solid_angle(j, width, map.height, hemisphere);
                region.radiance += radiance * dw;
                region.excess_luminance += (luminance - threshold) * dw;
                const glm::dvec3 direction = latlong::texel_direction(i, j, width, map.height);
                region.moment += luminance * dw * direction;
                region.excess_moment += (luminance - threshold) * dw * direction;
                const std::pair<int, int> neighbours[] = {
                    {(i + 1) % width, j}, {(i + width - 1) % width, j}, {i, j - 1}, {i, j + 1}};
                for (const auto& [ni, nj] : neighbours) {
                    if (nj < 0 || nj >= rows || visited[index(ni, nj)] || !above(ni, nj)) continue;
                    visited[index(ni, nj)] = 1;
                    stack.push_back({ni, nj});
                }
            }
        }
    }

    const double min_cos_radius = std::cos(kMaxCompactSourceRadiusDegrees * std::numbers::pi / 180.0);
    std::vector<std::pair<CompactSource, const Region*>> kept;
    for (const Region& region : regions) {
        if (!(region.excess_luminance > 0.0) || glm::length(region.moment) <= 0.0) continue;
        // The centre of the light taken (the glint lies there); the spread about it of the excess, the part
        // that makes the source compact: the cap with the same mean cosine (decompose.cpp's).
        const glm::dvec3 centre = glm::normalize(region.moment);
        const double mean_cos = glm::dot(centre, region.excess_moment) / region.excess_luminance;
        const double cos_radius = std::clamp(2.0 * mean_cos - 1.0, -1.0, 1.0);
        if (cos_radius < min_cos_radius) continue;
        kept.push_back({CompactSource{glm::vec3(centre), float(cos_radius), glm::vec3(region.radiance)}, &region});
    }
    std::ranges::sort(
        kept, [](const auto& a, const auto& b) { return a.second->excess_luminance > b.second->excess_luminance; });
    if (kept.size() > std::size_t(kMaxCompactSources)) kept.resize(std::size_t(kMaxCompactSources));
    for (const auto& [source, region] : kept) {
        for (const std::size_t t : region->texels) {
            glm::vec3& texel = split.rest.texels[t];
            texel = glm::vec3(0.0f);
        }
        split.sources.push_back(source);
    }
    return split;
}

}  // namespace envshadow
