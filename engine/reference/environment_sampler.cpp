#include "reference/environment_sampler.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>

#include "env/latlong.h"

namespace envshadow::reference {
namespace {

double luminance(const glm::vec3& rgb) {
    return latlong::luminance(glm::dvec3(glm::max(rgb, glm::vec3(0.0f))));
}

}  // namespace

glm::dmat3 world_from_map(double rotation_degrees) {
    return glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(rotation_degrees), glm::dvec3(0.0, 1.0, 0.0)));
}

EnvironmentSampler::EnvironmentSampler(const EnvironmentMap& map, double rotation_degrees)
    : map_(map), world_from_map_(world_from_map(rotation_degrees)), map_from_world_(glm::transpose(world_from_map_)) {
    const std::size_t count = std::size_t(map.width) * std::size_t(map.height);
    std::vector<double> solid_angle(std::size_t(map.height));
    for (int j = 0; j < map.height; ++j) {
        solid_angle[std::size_t(j)] = latlong::texel_solid_angle(j, map.width, map.height);
        for (int i = 0; i < map.width; ++i) total_ += luminance(map.at(i, j)) * solid_angle[std::size_t(j)];
    }
    const double mean = total_ / (4.0 * latlong::kPi);

    cumulative_.resize(count + 1);
    excess_.resize(count);
    row_start_.resize(std::size_t(map.height) + 1);
    cos_edge_.resize(std::size_t(map.height) + 1);
    cumulative_[0] = 0.0;
    std::size_t k = 0;
    for (int j = 0; j < map.height; ++j) {
        row_start_[std::size_t(j)] = cumulative_[k];
        cos_edge_[std::size_t(j)] = std::cos(latlong::kPi * j / map.height);
        for (int i = 0; i < map.width; ++i, ++k) {
            // Rounding in the mean must not leave a uniform map a speck of excess to sample.
            const double lum = luminance(map.at(i, j));
            excess_[k] = lum > mean * (1.0 + 1e-9) ? lum - mean : 0.0;
            cumulative_[k + 1] = cumulative_[k] + excess_[k] * solid_angle[std::size_t(j)];
        }
    }
    sampled_total_ = cumulative_[count];
    row_start_[std::size_t(map.height)] = sampled_total_;
    cos_edge_[std::size_t(map.height)] = -1.0;
}

double EnvironmentSampler::mean_luminance() const {
    return total_ / (4.0 * latlong::kPi);
}

std::size_t EnvironmentSampler::texel_index(const glm::dvec3& map_direction) const {
    const glm::dvec2 uv = latlong::uv(map_direction);
    const int i = std::min(int(uv.x * map_.width), map_.width - 1);
    const int j = std::min(int(uv.y * map_.height), map_.height - 1);
    return std::size_t(j) * std::size_t(map_.width) + std::size_t(i);
}

glm::dvec3 EnvironmentSampler::radiance(const glm::dvec3& world_direction) const {
    return glm::dvec3(map_.texels[texel_index(map_from_world_ * world_direction)]);
}

glm::dvec3 EnvironmentSampler::radiance_and_pdf(const glm::dvec3& world_direction, double& pdf) const {
    const std::size_t k = texel_index(map_from_world_ * world_direction);
    pdf = sampled_total_ > 0.0 ? excess_[k] / sampled_total_ : 0.0;
    return glm::dvec3(map_.texels[k]);
}

glm::dvec3 EnvironmentSampler::radiance_filtered(const glm::dvec3& world_direction) const {
    const glm::dvec2 uv = latlong::uv(map_from_world_ * world_direction);
    const double x = uv.x * map_.width - 0.5, y = uv.y * map_.height - 0.5;
    const double x0 = std::floor(x), y0 = std::floor(y);
    const double fx = x - x0, fy = y - y0;
    const auto column = [&](double c) { return int(((long long)c % map_.width + map_.width) % map_.width); };
    const auto row = [&](double r) { return std::clamp(int(r), 0, map_.height - 1); };
    const int i0 = column(x0), i1 = column(x0 + 1.0), j0 = row(y0), j1 = row(y0 + 1.0);
    const auto at = [&](int i, int j) { return glm::dvec3(map_.at(i, j)); };
    return (1.0 - fy) * ((1.0 - fx) * at(i0, j0) + fx * at(i1, j0)) + fy * ((1.0 - fx) * at(i0, j1) + fx * at(i1, j1));
}

EnvironmentSample EnvironmentSampler::sample(double xi1, double xi2) const {
    const std::size_t width = std::size_t(map_.width), height = std::size_t(map_.height);
    // The row j with row_start(j) <= target < row_start(j + 1), never one without light.
    const auto row_start = [&](std::size_t j) { return row_start_[j]; };
    const double row_target = xi1 * sampled_total_;
    const auto row = std::upper_bound(row_start_.begin(), row_start_.begin() + std::ptrdiff_t(height), row_target);
    std::size_t j = std::size_t(std::max<std::ptrdiff_t>(row - row_start_.begin() - 1, 0));
    while (j > 0 && row_start(j + 1) <= row_start(j)) --j;  // rounding onto an empty row's edge: the last lit one
    const double row_importance = row_start(j + 1) - row_start(j);
    const double along_row = std::clamp((row_target - row_start(j)) / row_importance, 0.0, 1.0);

    // The texel k of row j with cumulative_[k] <= column_target < cumulative_[k + 1].
    const double column_target = row_start(j) + xi2 * row_importance;
    const auto first = cumulative_.begin() + std::ptrdiff_t(j * width);
    auto it = std::upper_bound(first, first + std::ptrdiff_t(width), column_target);
    std::size_t k = std::size_t(std::max<std::ptrdiff_t>(it - cumulative_.begin() - 1, std::ptrdiff_t(j * width)));
    while (k > j * width && cumulative_[k + 1] <= cumulative_[k]) --k;
    const double texel_importance = cumulative_[k + 1] - cumulative_[k];
    const double along_texel = std::clamp((column_target - cumulative_[k]) / texel_importance, 0.0, 1.0);
    const std::size_t i = k - j * width;

    // Uniform in solid angle inside the texel: phi uniform, cos theta uniform between the row's edges.
    const double phi = 2.0 * latlong::kPi * (double(i) + along_texel) / map_.width;
    const double cos_top = cos_edge_[j], cos_bottom = cos_edge_[j + 1];
    const double cos_theta = cos_top + (cos_bottom - cos_top) * along_row;
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    const glm::dvec3 map_direction(sin_theta * std::cos(phi), cos_theta, sin_theta * std::sin(phi));

    const double solid_angle = latlong::texel_solid_angle(int(j), map_.width, map_.height);
    return {world_from_map_ * map_direction, texel_importance / (solid_angle * sampled_total_)};
}

double EnvironmentSampler::pdf(const glm::dvec3& world_direction) const {
    if (sampled_total_ <= 0.0) return 0.0;
    return excess_[texel_index(map_from_world_ * world_direction)] / sampled_total_;
}

}  // namespace envshadow::reference
