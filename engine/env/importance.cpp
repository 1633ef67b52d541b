#include "env/importance.h"

#include <tbb/parallel_for.h>

#include "env/latlong.h"

namespace envshadow {

int hemisphere_rows(int height, Hemisphere hemisphere) {
    return hemisphere == Hemisphere::full ? height : (height + 1) / 2;
}

double hemisphere_texel_solid_angle(int j, int width, int height, Hemisphere hemisphere) {
    if (hemisphere == Hemisphere::full) return latlong::texel_solid_angle(j, width, height);
    if (2 * j + 1 == height) return 0.5 * latlong::texel_solid_angle(j, width, height);  // cut by the horizon
    return j < hemisphere_rows(height, hemisphere) ? latlong::texel_solid_angle(j, width, height) : 0.0;
}

TexelDirections::TexelDirections(int width, int height, int rows) {
    if (rows < 0) rows = height;
    row_sin_.resize(size_t(rows));
    row_cos_.resize(size_t(rows));
    column_cos_.resize(size_t(width));
    column_sin_.resize(size_t(width));
    // latlong::direction(u, v) = (sin(pi v) cos(2 pi u), cos(pi v), sin(pi v) sin(2 pi u)): at u = 0 it
    // yields (sin theta, cos theta, 0) and at v = 1/2 (sin = 1 exactly) it yields (cos phi, ., sin phi).
    for (int j = 0; j < rows; ++j) {
        const glm::dvec3 d = latlong::direction(0.0, (j + 0.5) / height);
        row_sin_[size_t(j)] = d.x;
        row_cos_[size_t(j)] = d.y;
    }
    for (int i = 0; i < width; ++i) {
        const glm::dvec3 d = latlong::direction((i + 0.5) / width, 0.5);
        column_cos_[size_t(i)] = d.x;
        column_sin_[size_t(i)] = d.z;
    }
}

ImportanceMap build_importance(const EnvironmentMap& map, Hemisphere hemisphere) {
    ImportanceMap result;
    result.width = map.width;
    result.height = hemisphere_rows(map.height, hemisphere);
    result.map_height = map.height;
    result.directions = TexelDirections(map.width, map.height, result.height);
    result.row_solid_angle.resize(size_t(result.height));
    for (int j = 0; j < result.height; ++j)
        result.row_solid_angle[size_t(j)] = hemisphere_texel_solid_angle(j, map.width, map.height, hemisphere);
    result.importance.resize(size_t(map.width) * size_t(result.height));

    std::vector<double> row_total(static_cast<size_t>(result.height), 0.0);
    tbb::parallel_for(0, result.height, [&](int j) {
        const double dw = result.row_solid_angle[size_t(j)];
        double sum = 0.0;
        for (int i = 0; i < map.width; ++i) {
            const float value = float(latlong::luminance(glm::dvec3(map.at(i, j))) * dw);
            result.importance[size_t(j) * size_t(map.width) + size_t(i)] = value;
            sum += value;
        }
        row_total[size_t(j)] = sum;
    });
    for (double t : row_total) result.total += t;  // row order: independent of the thread count

    if (!(result.total > 0.0)) {
        result.uniform_fallback = true;
        result.total = 0.0;
        for (int j = 0; j < result.height; ++j) {
            const float dw = float(result.row_solid_angle[size_t(j)]);
            for (int i = 0; i < map.width; ++i) result.importance[size_t(j) * size_t(map.width) + size_t(i)] = dw;
            result.total += double(dw) * map.width;
        }
    }
    return result;
}

ImportanceMap downsample_importance(const ImportanceMap& fine, int factor) {
    ImportanceMap coarse;
    coarse.width = fine.width / factor;
    coarse.height = fine.height / factor;
    coarse.map_height = fine.lat_long_height() / factor;
    coarse.directions = TexelDirections(coarse.width, coarse.map_height, coarse.height);
    coarse.uniform_fallback = fine.uniform_fallback;
    coarse.row_solid_angle.resize(size_t(coarse.height));
    coarse.importance.assign(size_t(coarse.width) * size_t(coarse.height), 0.0f);
    for (int j = 0; j < coarse.height; ++j) {
        coarse.row_solid_angle[size_t(j)] = latlong::texel_solid_angle(j, coarse.width, coarse.map_height);
        for (int i = 0; i < coarse.width; ++i) {
            double sum = 0.0;
            for (int b = 0; b < factor; ++b)
                for (int a = 0; a < factor; ++a) sum += fine.at(i * factor + a, j * factor + b);
            coarse.importance[size_t(j) * size_t(coarse.width) + size_t(i)] = float(sum);
            coarse.total += float(sum);
        }
    }
    return coarse;
}

glm::dvec3 integrate_radiance(const EnvironmentMap& map, Hemisphere hemisphere) {
    const int rows = hemisphere_rows(map.height, hemisphere);
    std::vector<glm::dvec3> row_sum(size_t(rows), glm::dvec3(0.0));
    tbb::parallel_for(0, rows, [&](int j) {
        glm::dvec3 sum(0.0);
        for (int i = 0; i < map.width; ++i) sum += glm::dvec3(map.at(i, j));
        row_sum[size_t(j)] = sum * hemisphere_texel_solid_angle(j, map.width, map.height, hemisphere);
    });
    glm::dvec3 total(0.0);
    for (const glm::dvec3& s : row_sum) total += s;
    return total;
}

}  // namespace envshadow
