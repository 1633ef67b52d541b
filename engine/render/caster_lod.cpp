#include "render/caster_lod.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include <meshoptimizer.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace envshadow::render {

namespace {
// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
glm::vec3 closest_on_triangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f) return a;
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0f && d4 <= d3) return b;
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + ab * (d1 / (d1 - d3));
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0f && d5 <= d6) return c;
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + ac * (d2 / (d2 - d6));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const float denom = va + vb + vc;
    if (!(std::abs(denom) > 0.0f)) return a;  // degenerate triangle
    return a + ab * (vb / denom) + ac * (vc / denom);
}

// Dense ids 0, 1, 2, ... for 64-bit keys in the order they are first seen (open addressing, linear
// probing): the cells of a grid, the vertices of a submesh. No allocation per key, unlike
// std::unordered_map, whose nodes were most of a large model's memory.
class DenseIds {
public:
    static constexpr std::uint32_t kNone = ~0u;
    explicit DenseIds(std::size_t expected) { rehash(expected); }
    // The key's id; a new one (the number of keys so far) if it was not there.
    std::uint32_t insert(std::uint64_t key) {
        if (2 * (count_ + 1) > keys_.size()) rehash(2 * count_ + 2);
        std::size_t slot = hash(key) & mask_;
        while (keys_[slot] != kEmpty && keys_[slot] != key) slot = (slot + 1) & mask_;
        if (keys_[slot] == kEmpty) {
            keys_[slot] = key;
            ids_[slot] = count_++;
        }
        return ids_[slot];
    }
    std::uint32_t find(std::uint64_t key) const {
        for (std::size_t slot = hash(key) & mask_;; slot = (slot + 1) & mask_) {
            if (keys_[slot] == key) return ids_[slot];
            if (keys_[slot] == kEmpty) return kNone;
        }
    }
    std::uint32_t size() const { return count_; }

private:
    static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);  // no key used here has all 64 bits set
    static std::size_t hash(std::uint64_t key) {                // MurmurHash3's 64-bit finaliser
        key ^= key >> 33;
        key *= 0xff51afd7ed558ccdull;
        key ^= key >> 33;
        key *= 0xc4ceb9fe1a85ec53ull;
        return std::size_t(key ^ (key >> 33));
    }
    void rehash(std::size_t expected) {
        std::size_t size = 16;
        while (size < 2 * expected) size *= 2;
        std::vector<std::uint64_t> keys(size, kEmpty);
        std::vector<std::uint32_t> ids(size);
        for (std::size_t i = 0; i < keys_.size(); ++i) {
            if (keys_[i] == kEmpty) continue;
            std::size_t slot = hash(keys_[i]) & (size - 1);
            while (keys[slot] != kEmpty) slot = (slot + 1) & (size - 1);
            keys[slot] = keys_[i];
            ids[slot] = ids_[i];
        }
        keys_.swap(keys);
        ids_.swap(ids);
        mask_ = size - 1;
    }
    std::vector<std::uint64_t> keys_;
    std::vector<std::uint32_t> ids_;
    std::size_t mask_ = 0;
    std::uint32_t count_ = 0;
};

// The cell of size 1 / inverse_h holding p. Clamped to what an int holds (coordinates reach 1e12 m);
// cell keys keep 21 bits an axis anyway, so far cells share keys, which costs time, not exactness.
inline glm::ivec3 grid_cell(const glm::vec3& p, float inverse_h) {
    const auto cell = [inverse_h](float x) { return int(std::clamp(std::floor(x * inverse_h), -1e9f, 1e9f)); };
    return {cell(p.x), cell(p.y), cell(p.z)};
}

std::uint64_t cell_key(const glm::ivec3& c) {
    return (std::uint64_t(std::uint32_t(c.x) & 0x1fffffu) << 42) |
           (std::uint64_t(std::uint32_t(c.y) & 0x1fffffu) << 21) | std::uint64_t(std::uint32_t(c.z) & 0x1fffffu);
}

// The first and last grid cells (inclusive) of the bounding box of the triangle at indices[t ..].
std::pair<glm::ivec3, glm::ivec3> triangle_cells(std::span<const glm::vec3> positions,
                                                 std::span<const std::uint32_t> indices, std::size_t t,
                                                 float inverse_h) {
    const glm::vec3 a = positions[indices[t]], b = positions[indices[t + 1]], c = positions[indices[t + 2]];
    return {grid_cell(glm::min(a, glm::min(b, c)), inverse_h), grid_cell(glm::max(a, glm::max(b, c)), inverse_h)};
}

// Cells of size h that the triangles' bounding boxes cover, counted up to `limit`.
std::size_t covered_cells(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices, float h,
                          std::size_t limit) {
    std::size_t cells = 0;
    const float inverse_h = 1.0f / h;
    for (std::size_t t = 0; t + 2 < indices.size() && cells <= limit; t += 3) {
        const auto [lo, hi] = triangle_cells(positions, indices, t, inverse_h);
        const glm::ivec3 extent = hi - lo + 1;
        cells += std::size_t(extent.x) * std::size_t(extent.y) * std::size_t(extent.z);
    }
    return cells;
}

// The grid cell for measuring distances up to `wanted`: reach / 4^k, the smallest of those at least
// `wanted` and `smallest` (about the original's triangle size: finer cells hold no fewer triangles
// each), made coarser while the triangles would fill more than 8 cells each on average (large
// triangles: a flat part simplified to a few, a ground plane in the mesh), so that building the grid
// stays linear in the triangles.
float choose_cell(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices, float wanted,
                  float reach, float smallest) {
    float h = reach;
    while (h / 4.0f >= std::max({wanted, smallest, reach * 1e-6f})) h /= 4.0f;
    const std::size_t budget = 8 * (indices.size() / 3) + 4096;
    while (h < reach && covered_cells(positions, indices, h, budget) > budget) h *= 4.0f;
    return std::min(h, reach);
}

// Triangles bucketed in a uniform grid of cell size h (cells in one array, each cell's triangles
// contiguous): distance() is exact up to h (any triangle nearer than h lies in the 27 cells around the
// point) and reports h beyond. It may stop early with any distance at or below `enough` (the caller
// only wants the largest of many minima); `hint`, the triangle nearest the last point asked about,
// is tried first, which for points asked in mesh order usually settles it in one test.
class TriangleGrid {
public:
    static constexpr std::uint32_t kNoHint = ~0u;
    TriangleGrid(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices, float h)
        : positions_(positions), indices_(indices), h_(h), inverse_h_(1.0f / h), cells_(indices.size() / 24 + 16) {
        // Each triangle's cells numbered (consecutive triangles mostly share a cell: the last one is
        // remembered), counted, then the triangles placed cell by cell, in triangle order.
        std::vector<std::uint32_t> cell_of_pair, triangle_of_pair, counts;
        cell_of_pair.reserve(indices.size() / 3 + indices.size() / 12);
        triangle_of_pair.reserve(cell_of_pair.capacity());
        std::uint64_t last_key = ~std::uint64_t(0);
        std::uint32_t last_id = 0;
        for_each_cell([&](std::uint32_t t, const glm::ivec3& c) {
            const std::uint64_t key = cell_key(c);
            if (key != last_key) {
                last_key = key;
                last_id = cells_.insert(key);
                if (last_id == counts.size()) counts.push_back(0);
            }
            ++counts[last_id];
            cell_of_pair.push_back(last_id);
            triangle_of_pair.push_back(t);
        });
        first_.assign(counts.size() + 1, 0);
        for (std::size_t i = 0; i < counts.size(); ++i) first_[i + 1] = first_[i] + counts[i];
        triangles_.resize(first_.back());
        std::vector<std::uint32_t> next(first_.begin(), first_.end() - 1);
        for (std::size_t pair = 0; pair < cell_of_pair.size(); ++pair)
            triangles_[next[cell_of_pair[pair]]++] = triangle_of_pair[pair];
    }
    float cell_size() const { return h_; }
    float distance(const glm::vec3& p, float enough, std::uint32_t& hint) const {
        float best = h_;
        if (hint != kNoHint) {
            best = std::min(best, distance_to(p, hint));
            if (best <= enough) return best;
        }
        const glm::ivec3 c = grid_cell(p, inverse_h_);
        for (int n = 0; n < 27; ++n) {
            const int m = (n + 13) % 27;  // the point's own cell first
            const std::uint32_t id = cells_.find(cell_key(c + glm::ivec3(m % 3 - 1, (m / 3) % 3 - 1, m / 9 - 1)));
            if (id == DenseIds::kNone) continue;
            for (std::uint32_t i = first_[id]; i < first_[id + 1]; ++i) {
                const float d = distance_to(p, triangles_[i]);
                if (d < best) {
                    best = d;
                    hint = triangles_[i];
                    if (best <= enough) return best;
                }
            }
        }
        return best;
    }

private:
    float distance_to(const glm::vec3& p, std::uint32_t t) const {
        return glm::length(p - closest_on_triangle(p, positions_[indices_[t]], positions_[indices_[t + 1]],
                                                   positions_[indices_[t + 2]]));
    }
    template <class F>
    void for_each_cell(F&& f) const {
        for (std::uint32_t t = 0; t + 2 < indices_.size(); t += 3) {
            const auto [lo, hi] = triangle_cells(positions_, indices_, t, inverse_h_);
            for (int z = lo.z; z <= hi.z; ++z)
                for (int y = lo.y; y <= hi.y; ++y)
                    for (int x = lo.x; x <= hi.x; ++x) f(t, glm::ivec3(x, y, z));
        }
    }
    std::span<const glm::vec3> positions_;
    std::span<const std::uint32_t> indices_;
    float h_, inverse_h_;
    DenseIds cells_;
    std::vector<std::uint32_t> first_, triangles_;  // cell i holds triangles_[first_[i] .. first_[i + 1])
};

void raise_to(std::atomic<float>& worst, float value) {
    float seen = worst.load(std::memory_order_relaxed);
    while (value > seen && !worst.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
    }
}

// The largest of `count` point-to-surface distances point(i) -> grid, or `floor` if that is larger,
// on every core (TBB). Every query may stop at the largest distance found so far (shared between the
// threads), so most points cost one triangle test.
template <class Point>
float largest_distance(std::size_t count, const Point& point, const TriangleGrid& grid, float floor) {
    std::atomic<float> worst{floor};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          float enough = worst.load(std::memory_order_relaxed);
                          std::uint32_t hint = TriangleGrid::kNoHint;
                          for (std::size_t i = range.begin(); i != range.end(); ++i) {
                              const float d = grid.distance(point(i), enough, hint);
                              if (d > enough) {
                                  raise_to(worst, d);
                                  enough = worst.load(std::memory_order_relaxed);
                              }
                          }
                      });
    return worst.load();
}

// The original surface, for measuring simplified levels against it.
struct Original {
    std::span<const glm::vec3> positions;
    std::span<const std::uint32_t> indices;  // welded by position
    std::vector<std::uint32_t> vertices;     // each vertex the triangles use, once, in index order
    float reach = 0.0f;                      // distances are measured exactly up to this
    float triangle_size = 0.0f;              // square root of the mean triangle area: no finer grid cells
    std::optional<TriangleGrid> grid;
};

// Two-sided distance between the original surface and a simplified one, sampled: every original
// vertex to the simplified triangles, and every simplified triangle's centroid and edge midpoints to
// the original triangles (the simplified vertices are original vertices). The result is the larger
// of that distance and `floor` (below `reach`), exact as long as it is under `reach`; the grids' cells
// start at 4 times `floor`, are made 4 times coarser while a distance reaches a cell, and the
// original's grid is kept for the next, coarser level (its cells only grow).
float measured_error(Original& original, std::span<const std::uint32_t> simplified, float floor) {
    const std::span<const glm::vec3> positions = original.positions;
    float wanted = 4.0f * floor;
    for (;;) {
        if (!original.grid || original.grid->cell_size() < std::min(wanted, original.reach))
            original.grid.emplace(
                positions, original.indices,
                choose_cell(positions, original.indices, wanted, original.reach, 2.0f * original.triangle_size));
        const TriangleGrid simplified_grid(
            positions, simplified,
            choose_cell(positions, simplified, wanted, original.reach, 2.0f * original.triangle_size));
        const float cell = std::min(original.grid->cell_size(), simplified_grid.cell_size());
        const float to_simplified = largest_distance(
            original.vertices.size(), [&](std::size_t i) { return positions[original.vertices[i]]; }, simplified_grid,
            floor);
        const float to_original = largest_distance(
            4 * (simplified.size() / 3),
            [&](std::size_t i) {
                const std::size_t t = 3 * (i / 4);
                const glm::vec3 a = positions[simplified[t]], b = positions[simplified[t + 1]],
                                c = positions[simplified[t + 2]];
                switch (i % 4) {
                    case 0:
                        return (a + b + c) / 3.0f;
                    case 1:
                        return 0.5f * (a + b);
                    case 2:
                        return 0.5f * (b + c);
                    default:
                        return 0.5f * (c + a);
                }
            },
            *original.grid, to_simplified);
        if (to_original < cell || cell >= original.reach) return to_original;
        wanted = 4.0f * cell;  // some distance reaches a cell: measure it with coarser ones
    }
}

struct Simplified {
    std::vector<std::uint32_t> indices;  // into the mesh's vertex array, in vertex-cache order
    float error = 0.0f;                  // meshoptimizer's, in object space
};

// meshopt_simplify (to `target_error`, object space; 0 triangles targeted, so it stops where the next
// collapse would exceed it) on a copy of the submesh with only its own vertices: the library's passes
// each cost the whole vertex array it is given, which for the coarser levels of a large mesh is
// mostly vertices they no longer use. It also makes the weld work: given the whole array, the
// library takes a vertex that shares its position with one the welded triangles no longer use for
// an attribute seam and locks it (every seam of a glTF model's normals or texture coordinates).
Simplified simplify_submesh(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                            float target_error, unsigned options) {
    if (indices.empty()) return {};
    DenseIds local_of(indices.size() / 16 + 16);
    std::vector<std::uint32_t> local_indices(indices.size()), global_of;
    for (std::size_t i = 0; i < indices.size(); ++i) {
        local_indices[i] = local_of.insert(indices[i]);
        if (local_indices[i] == global_of.size()) global_of.push_back(indices[i]);
    }
    std::vector<glm::vec3> local_positions(global_of.size());
    for (std::size_t v = 0; v < global_of.size(); ++v) local_positions[v] = positions[global_of[v]];
    const float* xyz = &local_positions[0].x;
    // meshoptimizer's errors are relative to the extent of the vertices it is given.
    const float extent = meshopt_simplifyScale(xyz, local_positions.size(), sizeof(glm::vec3));
    if (!(extent > 0.0f)) return {};
    Simplified result;
    result.indices.resize(indices.size());
    float relative_error = 0.0f;
    result.indices.resize(meshopt_simplify(result.indices.data(), local_indices.data(), local_indices.size(), xyz,
                                           local_positions.size(), sizeof(glm::vec3), 0, target_error / extent, options,
                                           &relative_error));
    meshopt_optimizeVertexCache(result.indices.data(), result.indices.data(), result.indices.size(),
                                local_positions.size());
    for (std::uint32_t& index : result.indices) index = global_of[index];
    result.error = relative_error * extent;
    return result;
}

// Triangles in Morton order of their centroids (10 bits an axis over the bounding box of the
// vertices they use; three passes of a radix sort): consecutive runs are compact pieces of surface.
std::vector<std::uint32_t> morton_order(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices) {
    const std::size_t triangles = indices.size() / 3;
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
    for (std::uint32_t index : indices) {
        lo = glm::min(lo, positions[index]);
        hi = glm::max(hi, positions[index]);
    }
    const glm::vec3 to_grid = 1023.0f / glm::max(hi - lo, glm::vec3(1e-30f));
    const auto spread = [](std::uint32_t x) {  // 10 bits to every third of 30
        x = (x | (x << 16)) & 0x030000ffu;
        x = (x | (x << 8)) & 0x0300f00fu;
        x = (x | (x << 4)) & 0x030c30c3u;
        return (x | (x << 2)) & 0x09249249u;
    };
    std::vector<std::uint32_t> code(triangles), order(triangles), sorted(triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
        const glm::vec3 centroid =
            (positions[indices[3 * t]] + positions[indices[3 * t + 1]] + positions[indices[3 * t + 2]]) / 3.0f;
        const glm::uvec3 q = glm::uvec3(glm::clamp((centroid - lo) * to_grid, glm::vec3(0.0f), glm::vec3(1023.0f)));
        code[t] = (spread(q.x) << 2) | (spread(q.y) << 1) | spread(q.z);
        order[t] = std::uint32_t(t);
    }
    for (int shift = 0; shift < 30; shift += 10) {  // least significant digit first, stable
        std::vector<std::uint32_t> first(1025, 0);
        for (std::uint32_t t : order) ++first[((code[t] >> shift) & 1023u) + 1];
        for (std::size_t d = 0; d < 1024; ++d) first[d + 1] += first[d];
        for (std::uint32_t t : order) sorted[first[(code[t] >> shift) & 1023u]++] = t;
        order.swap(sorted);
    }
    return order;
}

// One level simplified from `source`, in chunks if it is large (CasterLodChunks). `progress` (the
// fraction of the chunks done) is called on the calling thread.
Simplified simplify_level(std::span<const glm::vec3> positions, std::span<const std::uint32_t> source,
                          float target_error, const CasterLodChunks& chunking,
                          const std::function<void(double)>& progress) {
    const std::size_t triangles = source.size() / 3;
    if (triangles <= chunking.chunked_from) return simplify_submesh(positions, source, target_error, 0);
    const std::vector<std::uint32_t> order = morton_order(positions, source);
    const std::size_t per_chunk = std::max<std::size_t>(chunking.chunk_triangles, 1);
    const std::size_t chunks = (triangles + per_chunk - 1) / per_chunk;
    std::vector<Simplified> parts(chunks);
    const std::size_t batch = 4 * std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    for (std::size_t first = 0; first < chunks; first += batch) {
        tbb::parallel_for(first, std::min(chunks, first + batch), [&](std::size_t c) {
            const std::size_t begin = c * triangles / chunks, end = (c + 1) * triangles / chunks;
            std::vector<std::uint32_t> chunk;
            chunk.reserve(3 * (end - begin));
            for (std::size_t i = begin; i < end; ++i)
                chunk.insert(chunk.end(), source.begin() + 3 * std::ptrdiff_t(order[i]),
                             source.begin() + 3 * std::ptrdiff_t(order[i]) + 3);
            parts[c] = simplify_submesh(positions, chunk, target_error, meshopt_SimplifyLockBorder);
        });
        if (progress) progress(double(std::min(chunks, first + batch)) / double(chunks));
    }
    Simplified result;
    for (const Simplified& part : parts) {
        result.indices.insert(result.indices.end(), part.indices.begin(), part.indices.end());
        result.error = std::max(result.error, part.error);
    }
    return result;
}
}  // namespace

CasterLod build_caster_lod(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                           const std::function<void(double fraction)>& progress, CasterLodChunks chunks) {
    CasterLod lod;
    lod.levels.push_back({0u, std::uint32_t(indices.size()), 0.0f, false});
    if (indices.empty() || positions.empty()) return lod;

    const float* xyz = &positions[0].x;
    // Weld vertices that share a position (seams of normals or texture coordinates): a depth map only
    // sees positions, and the simplifier keeps every seam as a border otherwise.
    std::vector<std::uint32_t> welded(indices.size());
    meshopt_generateShadowIndexBuffer(welded.data(), indices.data(), indices.size(), xyz, positions.size(),
                                      sizeof(glm::vec3), sizeof(glm::vec3));
    lod.levels[0].closed = is_closed(welded);
    if (indices.size() < 3 * 64) return lod;  // too small to be worth simplifying
    const float scale = meshopt_simplifyScale(xyz, positions.size(), sizeof(glm::vec3));
    if (!(scale > 0.0f) || !std::isfinite(scale)) return lod;  // every vertex at one point: nothing to simplify
    Original original{positions, welded, {}, scale / 64.0f, 0.0f, {}};  // errors up to 1/64 of the extent measured
    {
        std::vector<bool> used(positions.size(), false);
        for (std::uint32_t index : welded) used[index] = true;
        for (std::uint32_t v = 0; v < used.size(); ++v)
            if (used[v]) original.vertices.push_back(v);
        double area = 0.0;
        for (std::size_t t = 0; t < welded.size(); t += 3)
            area += 0.5 * double(glm::length(glm::cross(positions[welded[t + 1]] - positions[welded[t]],
                                                        positions[welded[t + 2]] - positions[welded[t]])));
        original.triangle_size = float(std::sqrt(area / double(welded.size() / 3)));
    }

    // Each level is simplified from the last one kept, not from the original: the simplifier's cost
    // then shrinks with the levels instead of being the full mesh's 16 times over. Its own error is
    // then relative to that level, so the bound it gives is the previous level's error plus it
    // (triangle inequality); the measured one is still against the original surface.
    std::vector<std::uint32_t> source;  // the last level kept; empty: the welded original
    std::uint32_t previous_count = std::uint32_t(indices.size());
    float previous_error = 0.0f;
    // Progress: the first target, simplified from the full mesh, is about half of the work (5 M
    // triangles: 4.8 of 10 s of CPU); each later one costs about the same, its error measurement
    // querying every original vertex.
    constexpr int kTargets = 17;  // 1/8192 to 1/32 by sqrt(2)
    constexpr double kFirstWeight = kTargets - 1;
    const auto report = [&](int target, double within) {
        if (progress)
            progress((target == 0 ? kFirstWeight * within : kFirstWeight + target - 1 + within) /
                     (kFirstWeight + kTargets - 1));
    };
    int tried = 0;
    for (float relative = 1.0f / 8192.0f; relative <= 1.0f / 32.0f; relative *= std::numbers::sqrt2_v<float>) {
        const int target = tried++;
        report(target, 0.0);
        const std::span<const std::uint32_t> from = source.empty() ? std::span<const std::uint32_t>(welded) : source;
        Simplified level = simplify_level(positions, from, relative * scale, chunks,
                                          [&](double chunks_done) { report(target, 0.5 * chunks_done); });
        const std::size_t count = level.indices.size();
        if (count == 0 || double(count) > 0.9 * double(previous_count)) continue;
        // meshoptimizer's error measures the kept vertices against the original faces' planes; the
        // new, larger triangles sag further between their vertices (2.5 times it on a finely
        // tessellated sphere, more on thin spikes). So the distance between the two surfaces is
        // measured (sampled at vertices, centroids and edge midpoints) and the larger one kept. Never
        // a level finer than the one before.
        const float bound = previous_error + level.error;
        const float measured = measured_error(original, level.indices, std::min(bound, 0.5f * original.reach));
        if (!(measured < original.reach)) break;  // beyond what is measured: coarser levels are useless
        const float error = std::max(measured, bound);
        lod.levels.push_back(
            {std::uint32_t(lod.indices.size()), std::uint32_t(count), error, is_closed(level.indices)});
        lod.indices.insert(lod.indices.end(), level.indices.begin(), level.indices.end());
        source = std::move(level.indices);
        previous_count = std::uint32_t(count);
        previous_error = error;
    }
    if (progress) progress(1.0);
    return lod;
}

int choose_caster_level(const CasterLod& lod, float max_error) {
    int chosen = 0;
    for (int k = 1; k < int(lod.levels.size()); ++k)
        if (lod.levels[std::size_t(k)].error <= max_error) chosen = k;
    return chosen;
}

float caster_error_budget(const glm::mat4& world_from_object, float min_texel_world, float fraction) {
    if (!(fraction > 0.0f) || !(min_texel_world > 0.0f)) return 0.0f;
    const float max_scale =
        std::max({glm::length(glm::vec3(world_from_object[0])), glm::length(glm::vec3(world_from_object[1])),
                  glm::length(glm::vec3(world_from_object[2]))});
    if (!(max_scale > 0.0f) || !std::isfinite(max_scale)) return 0.0f;
    return fraction * min_texel_world / max_scale;
}

void append_caster_tiles(const CasterLod& lod, const glm::mat4& world_from_object, std::span<const float> texel_world,
                         float fraction, CasterTiles& out) {
    std::vector<int> level_of(texel_world.size());
    int finest = int(lod.levels.size()), coarsest = -1;
    for (std::size_t k = 0; k < texel_world.size(); ++k) {
        level_of[k] = choose_caster_level(lod, caster_error_budget(world_from_object, texel_world[k], fraction));
        finest = std::min(finest, level_of[k]);
        coarsest = std::max(coarsest, level_of[k]);
    }
    for (int level = finest; level <= coarsest; ++level) {
        const std::uint32_t first = std::uint32_t(out.tiles.size());
        for (std::size_t k = 0; k < level_of.size(); ++k)
            if (level_of[k] == level) out.tiles.push_back(std::int32_t(k));
        const std::uint32_t count = std::uint32_t(out.tiles.size()) - first;
        if (count > 0) out.runs.push_back({level, first, count});
    }
}

}  // namespace envshadow::render
