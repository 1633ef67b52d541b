#include "render/lights.h"

#include <algorithm>
#include <numeric>

#include "env/latlong.h"

namespace envshadow::render {

LightSelection select_lights(std::span<const Cell> cells, const glm::mat3& world_from_map, bool has_ground, bool skip) {
    LightSelection selection;
    std::vector<WorldLight> lights;
    lights.reserve(cells.size());
    for (const Cell& cell : cells)
        lights.push_back({glm::normalize(world_from_map * cell.direction), cell.radiance, cell.cos_radius,
                          cell.cos_radius_weighted});
    if (!skip) {
        selection.kept = std::move(lights);
        return selection;
    }

    std::vector<double> luminance(lights.size());
    double total = 0.0;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        luminance[i] = std::max(0.0, latlong::luminance(glm::dvec3(lights[i].radiance)));
        total += luminance[i];
    }
    std::vector<bool> drop(lights.size(), false);
    for (std::size_t i = 0; i < lights.size(); ++i)
        if (has_ground && lights[i].direction.y < 0.0f) {
            drop[i] = true;
            ++selection.below_ground;
        }
    std::vector<std::size_t> order(lights.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return luminance[a] < luminance[b]; });
    double dropped = 0.0;
    for (std::size_t i : order) {
        if (drop[i]) continue;
        if (luminance[i] > 0.0 && dropped + luminance[i] > kNegligibleShare * total) break;
        dropped += luminance[i];
        drop[i] = true;
        ++selection.negligible;
    }
    for (std::size_t i = 0; i < lights.size(); ++i)
        if (!drop[i]) selection.kept.push_back(lights[i]);
    return selection;
}

}  // namespace envshadow::render
