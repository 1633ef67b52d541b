#include "render/lights.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec2.hpp>

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

namespace {

// Whether the directions `around` (unit vectors) leave no gap wider than kSurroundingGapDegrees in azimuth
// about `w`; directions within 0.2 (12 degrees) of w's axis have no azimuth to speak of and are left out.
bool surround(const glm::vec3& w, std::span<const glm::vec3> around) {
    const glm::vec3 t =
        glm::normalize(glm::cross(w, std::abs(w.y) < 0.9f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f)));
    const glm::vec3 b = glm::cross(w, t);
    std::vector<float> azimuths;
    for (const glm::vec3& d : around) {
        const glm::vec2 tangential(glm::dot(d, t), glm::dot(d, b));
        if (glm::length(tangential) > 0.2f) azimuths.push_back(std::atan2(tangential.y, tangential.x));
    }
    if (azimuths.empty()) return false;
    std::sort(azimuths.begin(), azimuths.end());
    float widest = azimuths.front() + 2.0f * std::numbers::pi_v<float> - azimuths.back();
    for (std::size_t k = 1; k < azimuths.size(); ++k) widest = std::max(widest, azimuths[k] - azimuths[k - 1]);
    return widest <= glm::radians(kSurroundingGapDegrees);
}

}  // namespace

std::vector<LightNeighbourhood> light_neighbourhoods(std::span<const WorldLight> lights) {
    if (lights.size() > std::size_t(kMaxLights))
        throw std::invalid_argument("light_neighbourhoods: " + std::to_string(lights.size()) + " lights, at most " +
                                    std::to_string(kMaxLights));
    const bool closed_below =
        std::all_of(lights.begin(), lights.end(), [](const WorldLight& l) { return l.direction.y >= 0.0f; });
    std::vector<float> radius(lights.size());
    for (std::size_t i = 0; i < lights.size(); ++i)
        radius[i] = std::acos(std::clamp(lights[i].cos_radius, -1.0f, 1.0f));
    std::vector<LightNeighbourhood> neighbourhoods(lights.size());
    std::vector<glm::vec3> around;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        around.clear();
        if (closed_below) around.push_back(glm::vec3(0.0f, -1.0f, 0.0f));
        for (std::size_t j = 0; j < lights.size(); ++j) {
            const float cos_apart = std::clamp(glm::dot(lights[i].direction, lights[j].direction), -1.0f, 1.0f);
            if (i != j && std::acos(cos_apart) > kNeighbourReach * (radius[i] + radius[j])) continue;
            neighbourhoods[i].lights[j / 32] |= std::uint32_t(1) << (j % 32);
            if (i != j) around.push_back(lights[j].direction);
        }
        neighbourhoods[i].surrounded = surround(lights[i].direction, around);
    }
    return neighbourhoods;
}

int sun_light(std::span<const LightRecord> lights) {
    int brightest = -1;
    double most = 0.0, total = 0.0;
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const double l = latlong::luminance(glm::dvec3(lights[i].radiance));
        total += l;
        if (l > most) {
            most = l;
            brightest = int(i);
        }
    }
    return most > 0.0 && most * double(lights.size()) >= kSunShare * total ? brightest : -1;
}

}  // namespace envshadow::render
