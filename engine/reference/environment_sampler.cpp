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
    std::vector<double> solid_angle(std::size_t(map.height)), lum(count);
    cos_edge_.resize(std::size_t(map.height) + 1);
    for (int j = 0; j < map.height; ++j) {
        solid_angle[std::size_t(j)] = latlong::texel_solid_angle(j, map.width, map.height);
        cos_edge_[std::size_t(j)] = std::cos(latlong::kPi * j / map.height);
        for (int i = 0; i < map.width; ++i) {
            const std::size_t k = std::size_t(j) * std::size_t(map.width) + std::size_t(i);
            lum[k] = luminance(map.at(i, j));
            total_ += lum[k] * solid_angle[std::size_t(j)];
        }
    }
    cos_edge_[std::size_t(map.height)] = -1.0;
    const double mean = total_ / (4.0 * latlong::kPi);

    // Rounding in the mean must not leave a uniform map a speck of excess to sample.
    std::vector<double> weight(count);
    for (std::size_t k = 0; k < count; ++k) weight[k] = lum[k] > mean * (1.0 + 1e-9) ? lum[k] - mean : 0.0;
    light_.cumulative.resize(count + 1);
    light_.row_start.resize(std::size_t(map.height) + 1);
    std::size_t k = 0;
    for (int j = 0; j < map.height; ++j) {
        light_.row_start[std::size_t(j)] = light_.cumulative[k];
        for (int i = 0; i < map.width; ++i, ++k)
            light_.cumulative[k + 1] = light_.cumulative[k] + weight[k] * solid_angle[std::size_t(j)];
    }
    light_.total = light_.cumulative[count];
    light_.row_start[std::size_t(map.height)] = light_.total;
    texels_.resize(count);
    for (k = 0; k < count; ++k) texels_[k] = {map.texels[k], light_.total > 0.0 ? weight[k] / light_.total : 0.0};
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
    const Texel& texel = texels_[texel_index(map_from_world_ * world_direction)];
    pdf = texel.pdf;
    return glm::dvec3(texel.radiance);
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
    const Distribution& light = light_;
    const std::size_t width = std::size_t(map_.width), height = std::size_t(map_.height);
    // The row j with row_start(j) <= target < row_start(j + 1), never one without weight.
    const std::vector<double>& row_start = light.row_start;
    const double row_target = xi1 * light.total;
    const auto row = std::upper_bound(row_start.begin(), row_start.begin() + std::ptrdiff_t(height), row_target);
    std::size_t j = std::size_t(std::max<std::ptrdiff_t>(row - row_start.begin() - 1, 0));
    while (j > 0 && row_start[j + 1] <= row_start[j]) --j;  // rounding onto an empty row's edge: the last lit one
    const double row_weight = row_start[j + 1] - row_start[j];
    const double along_row = std::clamp((row_target - row_start[j]) / row_weight, 0.0, 1.0);

    // The texel k of row j with cumulative[k] <= column_target < cumulative[k + 1].
    const std::vector<double>& cumulative = light.cumulative;
    const double column_target = row_start[j] + xi2 * row_weight;
    const auto first = cumulative.begin() + std::ptrdiff_t(j * width);
    auto it = std::upper_bound(first, first + std::ptrdiff_t(width), column_target);
    std::size_t k = std::size_t(std::max<std::ptrdiff_t>(it - cumulative.begin() - 1, std::ptrdiff_t(j * width)));
    while (k > j * width && cumulative[k + 1] <= cumulative[k]) --k;
    const double along_texel =
        std::clamp((column_target - cumulative[k]) / (cumulative[k + 1] - cumulative[k]), 0.0, 1.0);
    const std::size_t i = k - j * width;

    // Uniform in solid angle inside the texel: phi uniform, cos theta uniform between the row's edges.
    const double phi = 2.0 * latlong::kPi * (double(i) + along_texel) / map_.width;
    const double cos_top = cos_edge_[j], cos_bottom = cos_edge_[j + 1];
    const double cos_theta = cos_top + (cos_bottom - cos_top) * along_row;
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    const glm::dvec3 map_direction(sin_theta * std::cos(phi), cos_theta, sin_theta * std::sin(phi));
    // The density from the cumulative sums just searched (in cache), not from texels_ (a cache miss).
    const double solid_angle = (cos_top - cos_bottom) * 2.0 * latlong::kPi / map_.width;
    return {world_from_map_ * map_direction, (cumulative[k + 1] - cumulative[k]) / (solid_angle * light.total)};
}

double EnvironmentSampler::pdf(const glm::dvec3& world_direction) const {
    return texels_[texel_index(map_from_world_ * world_direction)].pdf;
}

}  // namespace envshadow::reference
