// Site placement without relaxation: random, Floyd-Steinberg, median cut; and the importance sampler
// the relaxations start from.
#include "env/sites.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace envshadow {
namespace {
// Floyd-Steinberg: the largest share of a block's error passed along its row (see floyd_steinberg_samples).
constexpr double kMaxAlongWeight = 15.0 / 16.0;
}  // namespace

double uniform01(std::mt19937_64& rng) {
    return double(rng() >> 11) * 0x1.0p-53;
}

std::vector<std::size_t> sample_distinct_texels(const ImportanceMap& importance, int count, std::mt19937_64& rng) {
    const std::size_t texels = importance.texel_count();
    std::vector<double> cdf(texels);
    double running = 0.0;
    for (std::size_t t = 0; t < texels; ++t) cdf[t] = running += importance.importance[t];

    std::vector<std::size_t> chosen;
    chosen.reserve(size_t(count));
    std::vector<bool> taken(texels, false);
    auto take = [&](std::size_t t) {
        if (taken[t]) return;
        taken[t] = true;
        chosen.push_back(t);
    };
    // Inverse CDF: the first texel whose running sum exceeds x never has zero importance.
    for (long attempt = 0; chosen.size() < size_t(count) && attempt < 64L * count + 1024; ++attempt) {
        const double x = uniform01(rng) * running;
        take(std::size_t(std::upper_bound(cdf.begin(), cdf.end(), x) - cdf.begin()));
    }
    // Fewer texels carry importance than sites are wanted: the rest in proportion to solid angle.
    if (chosen.size() < size_t(count)) {
        std::vector<double> row_cdf(static_cast<size_t>(importance.height));
        double rows = 0.0;
        for (int j = 0; j < importance.height; ++j) row_cdf[size_t(j)] = rows += importance.row_solid_angle[size_t(j)];
        for (long attempt = 0; chosen.size() < size_t(count) && attempt < 64L * count + 1024; ++attempt) {
            const double x = uniform01(rng) * rows;
            const std::size_t j = std::min<std::size_t>(
                size_t(importance.height) - 1,
                std::size_t(std::upper_bound(row_cdf.begin(), row_cdf.end(), x) - row_cdf.begin()));
            const std::size_t i =
                std::min<std::size_t>(size_t(importance.width) - 1, std::size_t(uniform01(rng) * importance.width));
            take(j * size_t(importance.width) + i);
        }
        for (std::size_t t = 0; chosen.size() < size_t(count) && t < texels; ++t) take(t);  // tiny maps
    }
    return chosen;
}

std::vector<glm::dvec3> texel_centres(const ImportanceMap& importance, std::span<const std::size_t> texels) {
    std::vector<glm::dvec3> sites;
    sites.reserve(texels.size());
    for (std::size_t t : texels)
        sites.push_back(importance.directions(int(t % size_t(importance.width)), int(t / size_t(importance.width))));
    return sites;
}

SiteSet sites_random(const ImportanceMap& importance, int count, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    SiteSet result;
    result.sites = texel_centres(importance, sample_distinct_texels(importance, count, rng));
    return result;
}

std::vector<glm::dvec3> floyd_steinberg_samples(const ImportanceMap& grid, std::span<const float> weight, int count,
                                                double start_error) {
    // Blocks of B x B texels, B a power of two, as small as keeps >= kBlocksPerSample blocks per sample.
    const int width = grid.width, height = grid.height;
    int block = 1;
    while (block < height) {
        const long long coarser =
            (long long)((width + 2 * block - 1) / (2 * block)) * ((height + 2 * block - 1) / (2 * block));
        if (coarser < (long long)kBlocksPerSample * count) break;
        block *= 2;
    }
    const int columns = (width + block - 1) / block, rows = (height + block - 1) / block;
    std::vector<double> blocks(size_t(columns) * size_t(rows), 0.0);
    double total = 0.0;
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) {
            const double w = weight[size_t(j) * size_t(width) + size_t(i)];
            blocks[size_t(j / block) * size_t(columns) + size_t(i / block)] += w;
            total += w;
        }

    const double threshold = total / (2.0 * count);
    std::vector<double> row_error(static_cast<size_t>(columns), 0.0), next_row_error(static_cast<size_t>(columns), 0.0);
    std::vector<std::pair<int, int>> chosen;
    double carried = start_error * threshold;
    for (int by = 0; by < rows; ++by) {
        const int step = by % 2 == 0 ? 1 : -1;  // serpentine
        const bool last_row = by == rows - 1;
        for (int n = 0; n < columns; ++n) {
            const int bx = step > 0 ? n : columns - 1 - n;
            double e = blocks[size_t(by) * size_t(columns) + size_t(bx)] + row_error[size_t(bx)] + carried;
            carried = 0.0;
            if (e > threshold) {
                chosen.emplace_back(bx, by);
                e -= 2.0 * threshold;
            }
            const bool last_in_row = n == columns - 1;
            const double gray = blocks[size_t(by) * size_t(columns) + size_t(bx)] / (2.0 * threshold);
            const double along = std::clamp(1.0 - gray, 0.375, kMaxAlongWeight);
            const double below_share = (1.0 - along) * 0.6, diagonal_share = (1.0 - along) * 0.4;
            // The block below-next wraps around the seam: on the sphere it is a neighbour, and the next
            // row has not been scanned yet.
            const int below_next = (bx + step + columns) % columns;
            if (!last_row) {
                if (!last_in_row) {
                    carried = along * e;
                    next_row_error[size_t(bx)] += below_share * e;
                } else {
                    next_row_error[size_t(bx)] += (along + below_share) * e;  // no next block: its share goes below
                }
                next_row_error[size_t(below_next)] += diagonal_share * e;
            } else if (!last_in_row) {
                carried = e;  // last row: everything goes on along the row
            }
        }
        std::swap(row_error, next_row_error);
        std::fill(next_row_error.begin(), next_row_error.end(), 0.0);
    }
    // A block fires at most once: where the count comes close to the number of blocks (or one block is
    // heavier than a sample), the error left at the end holds samples that could not fire. They go to the
    // heaviest blocks not chosen, up to count - 1 (the count is M or M - 1).
    if (int(chosen.size()) < std::max(1, count - 1)) {
        std::vector<bool> taken(blocks.size(), false);
        for (const auto& [bx, by] : chosen) taken[size_t(by) * size_t(columns) + size_t(bx)] = true;
        std::vector<size_t> order(blocks.size());
        for (size_t b = 0; b < order.size(); ++b) order[b] = b;
        std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return blocks[x] > blocks[y]; });
        for (size_t b : order) {
            if (int(chosen.size()) >= std::max(1, count - 1)) break;
            if (!taken[b]) chosen.emplace_back(int(b % size_t(columns)), int(b / size_t(columns)));
        }
    }
    // A sample stands at its block's weighted mean direction.
    std::vector<glm::dvec3> samples;
    for (const auto& [bx, by] : chosen) {
        CellMoments m;
        for (int j = by * block; j < std::min(height, (by + 1) * block); ++j)
            for (int i = bx * block; i < std::min(width, (bx + 1) * block); ++i)
                m.add(weight[size_t(j) * size_t(width) + size_t(i)], grid.row_solid_angle[size_t(j)],
                      grid.directions(i, j));
        const int ci = std::min(width - 1, bx * block + block / 2), cj = std::min(height - 1, by * block + block / 2);
        samples.push_back(centroid_direction(m, grid.directions(ci, cj)));
    }
    return samples;
}

SiteSet sites_floyd_steinberg(const ImportanceMap& importance, int count) {
    SiteSet result;
    result.sites = floyd_steinberg_samples(importance, importance.importance, count, 0.0);
    return result;
}

namespace {

// Summed-area table of importance: sum over [i0, i1) x [j0, j1) in O(1).
class ImportanceTable {
public:
    explicit ImportanceTable(const ImportanceMap& importance)
        : stride_(size_t(importance.width) + 1), sums_(stride_ * (size_t(importance.height) + 1), 0.0) {
        for (int j = 0; j < importance.height; ++j) {
            double row = 0.0;
            for (int i = 0; i < importance.width; ++i) {
                row += importance.at(i, j);
                sums_[(size_t(j) + 1) * stride_ + size_t(i) + 1] = sums_[size_t(j) * stride_ + size_t(i) + 1] + row;
            }
        }
    }
    double sum(int i0, int i1, int j0, int j1) const {
        return sums_[size_t(j1) * stride_ + size_t(i1)] - sums_[size_t(j0) * stride_ + size_t(i1)] -
               sums_[size_t(j1) * stride_ + size_t(i0)] + sums_[size_t(j0) * stride_ + size_t(i0)];
    }

private:
    std::size_t stride_;
    std::vector<double> sums_;
};

struct Region {
    int i0, i1, j0, j1;
    long long texels() const { return (long long)(i1 - i0) * (j1 - j0); }
};

// Splits `r` in two parts meant for `left` and `right` cells: across its angularly longest side (width
// measured at the middle latitude) where the left part holds left / (left + right) of its importance,
// each part keeping at least as many texels as cells where the shape allows. Returns false for a
// single texel.
bool split_region(const Region& r, int left, int right, const ImportanceTable& table, const ImportanceMap& importance,
                  Region& a, Region& b) {
    const double theta_mid = std::numbers::pi * 0.5 * (r.j0 + r.j1) / importance.lat_long_height();
    const double angular_width = (r.i1 - r.i0) * (2.0 * std::numbers::pi / importance.width) * std::sin(theta_mid);
    const double angular_height = (r.j1 - r.j0) * (std::numbers::pi / importance.lat_long_height());
    const double total = table.sum(r.i0, r.i1, r.j0, r.j1);
    const double fraction = double(left) / double(left + right);

    struct Choice {
        bool valid = false, across_columns = true, enough = false;
        int at = 0;
    } best;
    // Longest side first; the other side only if the longest cannot give both parts enough texels.
    const bool columns_first = angular_width >= angular_height;
    for (bool across_columns : {columns_first, !columns_first}) {
        const int lo = across_columns ? r.i0 : r.j0, hi = across_columns ? r.i1 : r.j1;
        const long long cross = across_columns ? (r.j1 - r.j0) : (r.i1 - r.i0);
        if (hi - lo < 2) continue;
        int first = lo + int(std::max<long long>(1, (left + cross - 1) / cross));
        int last = hi - int(std::max<long long>(1, (right + cross - 1) / cross));
        const bool enough = first <= last;
        if (!enough) first = last = std::clamp(lo + int(std::lround(fraction * (hi - lo))), lo + 1, hi - 1);
        auto left_sum = [&](int at) {
            return across_columns ? table.sum(r.i0, at, r.j0, r.j1) : table.sum(r.i0, r.i1, r.j0, at);
        };
        int at;
        if (total > 0.0) {
            // The first position whose left part holds the fraction, or the one before, whichever is closer.
            int lo_at = first, hi_at = last;
            while (lo_at < hi_at) {
                const int mid = lo_at + (hi_at - lo_at) / 2;
                if (left_sum(mid) >= fraction * total)
                    hi_at = mid;
                else
                    lo_at = mid + 1;
            }
            at = lo_at;
            if (at > first &&
                std::abs(left_sum(at - 1) - fraction * total) <= std::abs(left_sum(at) - fraction * total))
                --at;
        } else {
            at = std::clamp(lo + int(std::lround(fraction * (hi - lo))), first, last);
        }
        if (!best.valid || (!best.enough && enough)) best = {true, across_columns, enough, at};
        if (best.enough) break;
    }
    if (!best.valid) return false;
    a = b = r;
    if (best.across_columns) {
        a.i1 = best.at;
        b.i0 = best.at;
    } else {
        a.j1 = best.at;
        b.j0 = best.at;
    }
    return true;
}

// Leaves: regions and the number of cells each is meant for (more than one where it could not be split).
void split_recursively(const Region& r, int cells, const ImportanceTable& table, const ImportanceMap& importance,
                       std::vector<std::pair<Region, int>>& out) {
    Region a, b;
    if (cells <= 1 || !split_region(r, cells / 2, cells - cells / 2, table, importance, a, b)) {
        out.emplace_back(r, cells);
        return;
    }
    split_recursively(a, cells / 2, table, importance, out);
    split_recursively(b, cells - cells / 2, table, importance, out);
}

}  // namespace

std::vector<glm::dvec3> equal_importance_regions(const ImportanceMap& importance, int count) {
    const ImportanceTable table(importance);
    std::vector<std::pair<Region, int>> regions;
    split_recursively({0, importance.width, 0, importance.height}, count, table, importance, regions);
    std::vector<glm::dvec3> sites;
    std::vector<bool> taken(importance.texel_count(), false);
    int missing = 0;
    for (const auto& [r, cells] : regions) {
        CellMoments m;
        std::vector<std::size_t> texels;
        for (int j = r.j0; j < r.j1; ++j)
            for (int i = r.i0; i < r.i1; ++i) {
                m.add(importance.at(i, j), importance.row_solid_angle[size_t(j)], importance.directions(i, j));
                texels.push_back(size_t(j) * size_t(importance.width) + size_t(i));
            }
        const glm::dvec3 middle = importance.directions((r.i0 + r.i1) / 2, (r.j0 + r.j1) / 2);
        sites.push_back(centroid_direction(m, middle));
        // A region too small or too bright to split into its cells: the others at its heaviest texels
        // (only those sorted: the regions are a whole map's texels).
        if (cells > 1) {
            const std::size_t heaviest = std::min(texels.size(), std::size_t(cells - 1));
            std::partial_sort(texels.begin(), texels.begin() + std::ptrdiff_t(heaviest), texels.end(),
                              [&](std::size_t x, std::size_t y) {
                                  const float a = importance.importance[x], b = importance.importance[y];
                                  return a > b || (a == b && x < y);
                              });
        }
        for (int extra = 1; extra < cells; ++extra) {
            if (size_t(extra - 1) < texels.size()) {
                taken[texels[size_t(extra - 1)]] = true;
                sites.push_back(texel_centres(importance, std::span(&texels[size_t(extra - 1)], 1)).front());
            } else {
                ++missing;
            }
        }
    }
    // Still short (a region had fewer texels than cells): the heaviest texels not used yet.
    if (missing > 0) {
        std::vector<std::size_t> order(importance.texel_count());
        for (std::size_t t = 0; t < order.size(); ++t) order[t] = t;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
            return importance.importance[x] > importance.importance[y];
        });
        for (std::size_t t : order) {
            if (missing == 0) break;
            if (taken[t]) continue;
            sites.push_back(texel_centres(importance, std::span(&t, 1)).front());
            --missing;
        }
    }
    return sites;
}

SiteSet sites_median_cut(const ImportanceMap& importance, int count) {
    int power = 1;
    while (2 * power <= count) power *= 2;
    SiteSet result;
    result.sites = equal_importance_regions(importance, power);
    return result;
}

}  // namespace envshadow
