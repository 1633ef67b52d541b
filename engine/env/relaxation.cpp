// What the relaxations share: site moves, coarser problems, and the filling of empty cells.
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
namespace relaxation {

double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// A site whose cell holds no texel is moved next to the site of the cell with the largest
// importance x solid angle (the cell that most needs splitting), a quarter of that cell's radius away.
// Returns the largest jump, so that the relaxation goes on.
double reseed_empty_cells(std::vector<glm::dvec3>& sites, std::vector<double>* bias,
                          const std::vector<CellMoments>& cells) {
    double jump = 0.0;
    std::vector<double> weight(sites.size());
    for (size_t k = 0; k < sites.size(); ++k) weight[k] = cells[k].importance * cells[k].solid_angle;
    for (size_t k = 0; k < sites.size(); ++k) {
        if (cells[k].solid_angle > 0.0) continue;
        const size_t donor = size_t(std::max_element(weight.begin(), weight.end()) - weight.begin());
        weight[donor] *= 0.25;  // the next empty cell picks another donor unless this one still dominates
        const glm::dvec3 d = sites[donor];
        const glm::dvec3 axis = std::abs(d.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
        const glm::dvec3 tangent = glm::normalize(glm::cross(d, axis));
        const double offset = 0.25 * std::sqrt(cells[donor].solid_angle / std::numbers::pi);
        const glm::dvec3 moved = glm::normalize(d * std::cos(offset) + tangent * std::sin(offset));
        jump = std::max(jump, angle_between(moved, sites[k]));
        sites[k] = moved;
        if (bias) (*bias)[k] = (*bias)[donor];
    }
    return jump;
}

// A copy of `importance` box-blurred over (2 radius + 1)^2 texels (wrapping around the seam, clamped at
// the poles) and scaled back to the same total: a smoother problem to start the capacity solve on.
ImportanceMap blurred(const ImportanceMap& importance, int radius) {
    const int w = importance.width, h = importance.height;
    ImportanceMap out = importance;
    std::vector<double> rows(importance.importance.size());
    tbb::parallel_for(0, h, [&](int j) {
        double sum = 0.0;  // running box sum along the row
        for (int d = -radius; d <= radius; ++d) sum += importance.at(((d % w) + w) % w, j);
        for (int i = 0; i < w; ++i) {
            rows[size_t(j) * size_t(w) + size_t(i)] = sum;
            sum += importance.at((i + radius + 1) % w, j) - importance.at(((i - radius) % w + w) % w, j);
        }
    });
    tbb::parallel_for(0, w, [&](int i) {
        double sum = 0.0;
        for (int d = -radius; d <= radius; ++d) sum += rows[size_t(std::clamp(d, 0, h - 1)) * size_t(w) + size_t(i)];
        for (int j = 0; j < h; ++j) {
            out.importance[size_t(j) * size_t(w) + size_t(i)] = float(std::max(0.0, sum));
            sum += rows[size_t(std::clamp(j + radius + 1, 0, h - 1)) * size_t(w) + size_t(i)] -
                   rows[size_t(std::clamp(j - radius, 0, h - 1)) * size_t(w) + size_t(i)];
        }
    });
    double total = 0.0;
    for (float v : out.importance) total += v;
    const double scale = total > 0.0 ? importance.total / total : 1.0;
    for (float& v : out.importance) v = float(v * scale);
    return out;
}

// Whether the map can be taken to 1/factor of its resolution: factor divides it (the rows held and the
// whole map's) and leaves at least 16 rows.
bool coarsens(const ImportanceMap& fine, int factor) {
    return factor > 1 && fine.width % factor == 0 && fine.height % factor == 0 &&
           fine.lat_long_height() % factor == 0 && fine.height / factor >= 16;
}

// At full resolution where the map does not coarsen by `factor`.
Resolution at_resolution(const ImportanceMap& fine, int factor, int blur, SiteSearch search) {
    if (!coarsens(fine, factor)) factor = 1;
    Resolution r;
    r.importance = std::make_unique<ImportanceMap>(factor > 1 ? downsample_importance(fine, factor) : fine);
    if (blur > 0) *r.importance = blurred(*r.importance, blur);
    r.partition.emplace(*r.importance, search);
    return r;
}

}  // namespace relaxation

int fill_empty_cells(const ImportanceMap& importance, const Partition& partition, std::vector<glm::dvec3>& sites,
                     std::vector<double>& bias, std::span<std::uint16_t> texel_cell, int max_rounds) {
    const std::size_t count = sites.size();
    int rounds = 0;
    for (; rounds < max_rounds; ++rounds) {
        std::vector<long> texels(count, 0);
        for (std::uint16_t k : texel_cell) ++texels[k];
        if (std::find(texels.begin(), texels.end(), 0L) == texels.end()) break;
        // The texel each site stands on, which its cell keeps.
        std::vector<std::size_t> own(count);
        for (std::size_t k = 0; k < count; ++k) {
            const glm::dvec2 uv = latlong::uv(sites[k]);
            const int i = std::min(importance.width - 1, int(uv.x * importance.width));
            const int j = std::min(importance.height - 1, int(uv.y * importance.lat_long_height()));
            own[k] = std::size_t(j) * std::size_t(importance.width) + std::size_t(i);
        }
        std::vector<double> mass(count, 0.0), solid_angle(count, 0.0);
        std::vector<std::size_t> heaviest(count, texel_cell.size());
        for (std::size_t t = 0; t < texel_cell.size(); ++t) {
            const std::size_t k = texel_cell[t];
            mass[k] += importance.importance[t];
            solid_angle[k] += importance.row_solid_angle[t / std::size_t(importance.width)];
            if (t != own[k] &&
                (heaviest[k] == texel_cell.size() || importance.importance[t] > importance.importance[heaviest[k]]))
                heaviest[k] = t;
        }
        std::vector<double> weight(count);
        for (std::size_t k = 0; k < count; ++k)
            weight[k] = texels[k] >= 2 && heaviest[k] < texel_cell.size() ? mass[k] * solid_angle[k] + 1e-300 : -1.0;
        for (std::size_t k = 0; k < count; ++k) {
            if (texels[k] > 0) continue;
            const std::size_t donor = std::size_t(std::max_element(weight.begin(), weight.end()) - weight.begin());
            if (weight[donor] < 0.0) break;  // no cell left to give a texel this round
            weight[donor] = -1.0;            // one texel per donor and round
            sites[k] = texel_centres(importance, std::span(&heaviest[donor], 1)).front();
            if (!bias.empty()) bias[k] = bias[donor];
        }
        partition.assign(sites, bias, texel_cell);
    }
    return rounds;
}

}  // namespace envshadow
