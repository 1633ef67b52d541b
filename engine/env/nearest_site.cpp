#include "env/nearest_site.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "env/latlong.h"

namespace envshadow {
namespace {

constexpr int kTopTileSize = 128;   // texels per side of the coarsest tiles
constexpr int kChunkTileSize = 32;  // a row of these tiles is one unit of parallel work
// Below the leaf size, texels are scored one by one against the candidates. 8 x 8 rather than 4 x 4:
// a quarter of the tiles' caps and moments to allocate and touch (fresh pages cost a first run most),
// and the same cells.
constexpr int kLeafTileSize = 8;
constexpr int kLevels = 5;  // 128, 64, 32, 16, 8
constexpr int kChunkLevel = 2;
static_assert(kTopTileSize >> (kLevels - 1) == kLeafTileSize && kTopTileSize >> kChunkLevel == kChunkTileSize);
constexpr int kRowsPerChunk = 8;  // partition_moments: rows summed together before the ordered reduction

// Slack on the pruning test: a site is dropped only if its best score in the tile is below another
// site's worst score by this much. Rounding in the bounds is ~1e-15, so no texel the brute force would
// give to a dropped site exists.
constexpr double kPruneMargin = 1e-9;

struct SiteRecord {
    double x, y, z, bias;
};

// The single definition of a site's score, shared by the brute force and the tile search so that both
// compare bit-identical numbers.
inline double score(const glm::dvec3& p, const SiteRecord& s) {
    return p.x * s.x + p.y * s.y + p.z * s.z + s.bias;
}

std::vector<SiteRecord> pack_sites(std::span<const glm::dvec3> sites, std::span<const double> bias) {
    std::vector<SiteRecord> records(sites.size());
    for (size_t k = 0; k < sites.size(); ++k)
        records[k] = {sites[k].x, sites[k].y, sites[k].z, bias.empty() ? 0.0 : bias[k]};
    return records;
}

inline int best_site(const glm::dvec3& p, const SiteRecord* sites, const std::uint16_t* candidates, int count) {
    int best = candidates[0];
    double best_score = score(p, sites[best]);
    for (int c = 1; c < count; ++c) {
        const double s = score(p, sites[candidates[c]]);
        if (s > best_score) {
            best_score = s;
            best = candidates[c];
        }
    }
    return best;
}

// Keeps, in index order, the candidates whose highest score over the cap can reach the lowest score
// over the cap of the site that wins at the cap's centre. For a site at angle a from the centre of a cap
// of radius r, p . s over the cap lies in [cos(min(pi, a + r)), cos(max(0, a - r))].
int prune(const NearestSiteSearch::Cap& tile, const SiteRecord* sites, const std::uint16_t* in, int count,
          std::uint16_t* out, double* centre_cos) {
    const double cr = tile.cos_radius, sr = tile.sin_radius;
    int best = 0;
    double best_score = -std::numeric_limits<double>::infinity();
    for (int c = 0; c < count; ++c) {
        const SiteRecord& s = sites[in[c]];
        const double ca = tile.centre.x * s.x + tile.centre.y * s.y + tile.centre.z * s.z;
        centre_cos[c] = ca;
        if (ca + s.bias > best_score) {
            best_score = ca + s.bias;
            best = c;
        }
    }
    const double cb = centre_cos[best];
    const double lowest =
        (cb <= -cr ? -1.0 : cb * cr - std::sqrt(std::max(0.0, 1.0 - cb * cb)) * sr) + sites[in[best]].bias;
    const double threshold = lowest - kPruneMargin;
    const double sr2 = sr * sr;
    int kept = 0;
    for (int c = 0; c < count; ++c) {
        const double ca = centre_cos[c];
        const double needed = threshold - sites[in[c]].bias;  // the site's highest p . s must reach this
        // Inside the cap, the site itself is reachable (p . s = 1); outside, cos(a - r) = ca cr + sa sr
        // must reach `needed`, compared squared to avoid the square root. Branch-free: the outcome is
        // unpredictable.
        const double rest = needed - ca * cr;
        const bool inside = ca >= cr;
        const bool reaches = rest <= 0.0 || std::max(0.0, 1.0 - ca * ca) * sr2 >= rest * rest;
        const bool keep = (inside & (needed <= 1.0)) | (!inside & reaches);
        out[kept] = in[c];
        kept += int(keep);
    }
    return kept;
}

// The bounding cap of the texel centres of [i0, i1) x [j0, j1).
NearestSiteSearch::Cap make_cap(const ImportanceMap& importance, int i0, int i1, int j0, int j1) {
    NearestSiteSearch::Cap tile;
    if (i1 - i0 > importance.width / 4) return tile;  // over pi/2 of longitude: the whole sphere is the cap
    // The corners' sum lies on the rectangle's middle meridian. Seen from any point of that meridian, with
    // at most pi/4 of longitude on either side, the angle grows along every edge of the rectangle towards
    // its ends, so the farthest texel centres are corners.
    const glm::dvec3 corners[4] = {importance.directions(i0, j0), importance.directions(i1 - 1, j0),
                                   importance.directions(i0, j1 - 1), importance.directions(i1 - 1, j1 - 1)};
    const glm::dvec3 sum = corners[0] + corners[1] + corners[2] + corners[3];
    if (glm::length(sum) < 1e-6) return tile;
    tile.centre = glm::normalize(sum);
    double cos_radius = 1.0;
    for (const glm::dvec3& c : corners) cos_radius = std::min(cos_radius, glm::dot(tile.centre, c));
    tile.cos_radius = std::max(-1.0, cos_radius - 1e-12);  // slightly larger than needed
    tile.sin_radius = std::sqrt(std::max(0.0, 1.0 - tile.cos_radius * tile.cos_radius));
    return tile;
}

using Level = NearestSiteSearch::Level;

// Candidate lists of the tiles of the level above the chunk level, pruned from the top down (serial:
// there are few such tiles).
std::vector<std::vector<std::uint16_t>> coarse_candidates(const std::vector<Level>& levels,
                                                          const std::vector<SiteRecord>& sites) {
    const int count = int(sites.size());
    std::vector<std::uint16_t> all(static_cast<size_t>(count));
    for (int k = 0; k < count; ++k) all[size_t(k)] = std::uint16_t(k);
    std::vector<std::vector<std::uint16_t>> result(levels[kChunkLevel - 1].caps.size());
    std::array<std::vector<std::uint16_t>, kChunkLevel> lists;
    for (auto& list : lists) list.resize(size_t(count));
    std::vector<double> centre_cos(static_cast<size_t>(count));
    auto visit = [&](auto&& self, int l, int tx, int ty, const std::uint16_t* in, int n) -> void {
        const Level& level = levels[size_t(l)];
        std::uint16_t* out = lists[size_t(l)].data();
        const int kept = n == 1 ? (out[0] = in[0], 1)
                                : prune(level.caps[level.index(tx, ty)], sites.data(), in, n, out, centre_cos.data());
        if (l == kChunkLevel - 1) {
            result[level.index(tx, ty)].assign(out, out + kept);
            return;
        }
        const Level& finer = levels[size_t(l) + 1];
        for (int cy = 2 * ty; cy < std::min(finer.rows, 2 * ty + 2); ++cy)
            for (int cx = 2 * tx; cx < std::min(finer.columns, 2 * tx + 2); ++cx) self(self, l + 1, cx, cy, out, kept);
    };
    for (int ty = 0; ty < levels[0].rows; ++ty)
        for (int tx = 0; tx < levels[0].columns; ++tx) visit(visit, 0, tx, ty, all.data(), count);
    return result;
}

// Visits the tiles of one chunk (a row of chunk-level tiles), coarse to fine, calling
// visitor.tile(level, tx, ty, site) for a tile won entirely by one site and
// visitor.texel(i, j, p, site) for the texels of leaf tiles still shared by several candidates.
template <class Visitor>
void traverse_chunk(const std::vector<Level>& levels, const ImportanceMap& importance,
                    const std::vector<SiteRecord>& sites, const std::vector<std::vector<std::uint16_t>>& coarse,
                    int chunk, Visitor& visitor) {
    const int count = int(sites.size());
    std::array<std::vector<std::uint16_t>, kLevels> lists;
    for (auto& list : lists) list.resize(size_t(count));
    std::vector<double> centre_cos(static_cast<size_t>(count));

    auto visit = [&](auto&& self, int l, int tx, int ty, const std::uint16_t* in, int n) -> void {
        const Level& level = levels[size_t(l)];
        const NearestSiteSearch::Cap& tile = level.caps[level.index(tx, ty)];
        std::uint16_t* out = lists[size_t(l)].data();
        const int kept = n == 1 ? (out[0] = in[0], 1) : prune(tile, sites.data(), in, n, out, centre_cos.data());
        if (kept == 1) {
            visitor.tile(l, tx, ty, out[0]);
            return;
        }
        const int s = level.tile_size;
        if (l == kLevels - 1) {
            const int i0 = tx * s, i1 = std::min(importance.width, i0 + s);
            const int j0 = ty * s, j1 = std::min(importance.height, j0 + s);
            for (int j = j0; j < j1; ++j)
                for (int i = i0; i < i1; ++i) {
                    const glm::dvec3 p = importance.directions(i, j);
                    visitor.texel(i, j, p, best_site(p, sites.data(), out, kept));
                }
            return;
        }
        const Level& finer = levels[size_t(l) + 1];
        for (int cy = 2 * ty; cy < std::min(finer.rows, 2 * ty + 2); ++cy)
            for (int cx = 2 * tx; cx < std::min(finer.columns, 2 * tx + 2); ++cx) self(self, l + 1, cx, cy, out, kept);
    };
    const Level& parent = levels[kChunkLevel - 1];
    for (int tx = 0; tx < levels[kChunkLevel].columns; ++tx) {
        const std::vector<std::uint16_t>& in = coarse[parent.index(tx / 2, chunk / 2)];
        visit(visit, kChunkLevel, tx, chunk, in.data(), int(in.size()));
    }
}

}  // namespace

glm::dvec3 centroid_direction(const CellMoments& m, const glm::dvec3& fallback) {
    // A mean shorter than 1e-9 of its weight has no meaningful direction.
    if (m.importance > 0.0) {
        const double length = glm::length(m.importance_direction);
        if (length > 1e-9 * m.importance) return m.importance_direction / length;
    }
    if (m.solid_angle > 0.0) {
        const double length = glm::length(m.solid_angle_direction);
        if (length > 1e-9 * m.solid_angle) return m.solid_angle_direction / length;
    }
    return fallback;
}

void assign_nearest_brute_force(const ImportanceMap& importance, std::span<const glm::dvec3> sites,
                                std::span<const double> bias, std::span<std::uint16_t> texel_cell) {
    const std::vector<SiteRecord> records = pack_sites(sites, bias);
    const int count = int(records.size());
    tbb::parallel_for(0, importance.height, [&](int j) {
        for (int i = 0; i < importance.width; ++i) {
            const glm::dvec3 p = importance.directions(i, j);
            int best = 0;
            double best_score = score(p, records[0]);
            for (int k = 1; k < count; ++k) {
                const double s = score(p, records[size_t(k)]);
                if (s > best_score) {
                    best_score = s;
                    best = k;
                }
            }
            texel_cell[size_t(j) * size_t(importance.width) + size_t(i)] = std::uint16_t(best);
        }
    });
}

std::vector<CellMoments> partition_moments(const ImportanceMap& importance, std::span<const std::uint16_t> texel_cell,
                                           int cell_count) {
    const int chunks = (importance.height + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<std::vector<CellMoments>> partial(static_cast<size_t>(chunks),
                                                  std::vector<CellMoments>(static_cast<size_t>(cell_count)));
    tbb::parallel_for(0, chunks, [&](int chunk) {
        std::vector<CellMoments>& acc = partial[size_t(chunk)];
        for (int j = chunk * kRowsPerChunk; j < std::min(importance.height, (chunk + 1) * kRowsPerChunk); ++j)
            for (int i = 0; i < importance.width; ++i) {
                const size_t t = size_t(j) * size_t(importance.width) + size_t(i);
                acc[texel_cell[t]].add(importance.importance[t], importance.row_solid_angle[size_t(j)],
                                       importance.directions(i, j));
            }
    });
    std::vector<CellMoments> total(static_cast<size_t>(cell_count));
    for (const auto& p : partial)
        for (size_t k = 0; k < total.size(); ++k) total[k] += p[k];
    return total;
}

NearestSiteSearch::NearestSiteSearch(const ImportanceMap& importance) : importance_(&importance) {
    const int width = importance.width, height = importance.height;
    levels_.resize(kLevels);
    for (int l = 0; l < kLevels; ++l) {
        Level& level = levels_[size_t(l)];
        level.tile_size = kTopTileSize >> l;
        level.columns = (width + level.tile_size - 1) / level.tile_size;
        level.rows = (height + level.tile_size - 1) / level.tile_size;
        level.block = l > kChunkLevel ? 1 << (l - kChunkLevel) : 1;
        level.block_columns = (level.columns + level.block - 1) / level.block;
        const int block_rows = (level.rows + level.block - 1) / level.block;
        level.caps.resize(size_t(level.block_columns) * size_t(block_rows) * size_t(level.block * level.block));
        level.moments.resize(level.caps.size());
    }
    // Caps for every level; texel moments into the leaves; coarser moments as sums of their children.
    for (int l = 0; l < kLevels; ++l) {
        Level& level = levels_[size_t(l)];
        const int s = level.tile_size;
        const bool leaf = l == kLevels - 1;
        tbb::parallel_for(0, level.rows, [&](int ty) {
            for (int tx = 0; tx < level.columns; ++tx) {
                const int i0 = tx * s, i1 = std::min(width, i0 + s), j0 = ty * s, j1 = std::min(height, j0 + s);
                const size_t t = level.index(tx, ty);
                level.caps[t] = make_cap(importance, i0, i1, j0, j1);
                if (!leaf) continue;
                for (int j = j0; j < j1; ++j)
                    for (int i = i0; i < i1; ++i)
                        level.moments[t].add(importance.at(i, j), importance.row_solid_angle[size_t(j)],
                                             importance.directions(i, j));
            }
        });
    }
    for (int l = kLevels - 2; l >= 0; --l) {
        Level& level = levels_[size_t(l)];
        const Level& finer = levels_[size_t(l) + 1];
        for (int ty = 0; ty < level.rows; ++ty)
            for (int tx = 0; tx < level.columns; ++tx) {
                CellMoments& m = level.moments[level.index(tx, ty)];
                for (int cy = 2 * ty; cy < std::min(finer.rows, 2 * ty + 2); ++cy)
                    for (int cx = 2 * tx; cx < std::min(finer.columns, 2 * tx + 2); ++cx)
                        m += finer.moments[finer.index(cx, cy)];
            }
    }
}

void NearestSiteSearch::assign(std::span<const glm::dvec3> sites, std::span<const double> bias,
                               std::span<std::uint16_t> texel_cell) const {
    const int width = importance_->width, height = importance_->height;
    struct Assign {
        const std::vector<Level>& levels;
        std::span<std::uint16_t> texel_cell;
        int width, height;
        void tile(int l, int tx, int ty, int site) {
            const int s = levels[size_t(l)].tile_size;
            const int i0 = tx * s, i1 = std::min(width, i0 + s), j1 = std::min(height, ty * s + s);
            for (int j = ty * s; j < j1; ++j)
                std::fill(texel_cell.begin() + std::ptrdiff_t(size_t(j) * size_t(width) + size_t(i0)),
                          texel_cell.begin() + std::ptrdiff_t(size_t(j) * size_t(width) + size_t(i1)),
                          std::uint16_t(site));
        }
        void texel(int i, int j, const glm::dvec3&, int site) {
            texel_cell[size_t(j) * size_t(width) + size_t(i)] = std::uint16_t(site);
        }
    };
    const std::vector<SiteRecord> records = pack_sites(sites, bias);
    const auto coarse = coarse_candidates(levels_, records);
    tbb::parallel_for(0, levels_[kChunkLevel].rows, [&](int chunk) {
        Assign visitor{levels_, texel_cell, width, height};
        traverse_chunk(levels_, *importance_, records, coarse, chunk, visitor);
    });
}

std::vector<CellMoments> NearestSiteSearch::moments(std::span<const glm::dvec3> sites,
                                                    std::span<const double> bias) const {
    struct Accumulate {
        const std::vector<Level>& levels;
        const ImportanceMap& importance;
        std::vector<CellMoments>& cells;
        void tile(int l, int tx, int ty, int site) {
            const Level& level = levels[size_t(l)];
            cells[size_t(site)] += level.moments[level.index(tx, ty)];
        }
        void texel(int i, int j, const glm::dvec3& p, int site) {
            cells[size_t(site)].add(importance.at(i, j), importance.row_solid_angle[size_t(j)], p);
        }
    };
    const std::vector<SiteRecord> records = pack_sites(sites, bias);
    const auto coarse = coarse_candidates(levels_, records);
    const int chunks = levels_[kChunkLevel].rows;
    std::vector<std::vector<CellMoments>> partial(static_cast<size_t>(chunks), std::vector<CellMoments>(sites.size()));
    tbb::parallel_for(0, chunks, [&](int chunk) {
        Accumulate visitor{levels_, *importance_, partial[size_t(chunk)]};
        traverse_chunk(levels_, *importance_, records, coarse, chunk, visitor);
    });
    std::vector<CellMoments> total(sites.size());
    for (const auto& p : partial)
        for (size_t k = 0; k < total.size(); ++k) total[k] += p[k];
    return total;
}

Partition::Partition(const ImportanceMap& importance, SiteSearch search) : importance_(&importance), search_(search) {}

const NearestSiteSearch& Partition::tiles() const {
    if (!tiles_) tiles_.emplace(*importance_);
    return *tiles_;
}

std::vector<CellMoments> Partition::moments(std::span<const glm::dvec3> sites, std::span<const double> bias) const {
    if (search_ == SiteSearch::tiles) return tiles().moments(sites, bias);
    std::vector<std::uint16_t> texel_cell(importance_->texel_count());
    assign_nearest_brute_force(*importance_, sites, bias, texel_cell);
    return partition_moments(*importance_, texel_cell, int(sites.size()));
}

void Partition::assign(std::span<const glm::dvec3> sites, std::span<const double> bias,
                       std::span<std::uint16_t> texel_cell) const {
    if (search_ == SiteSearch::tiles)
        tiles().assign(sites, bias, texel_cell);
    else
        assign_nearest_brute_force(*importance_, sites, bias, texel_cell);
}

}  // namespace envshadow
