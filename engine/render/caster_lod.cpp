#include "render/caster_lod.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include <meshoptimizer.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
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

// Triangles bucketed in a uniform grid of cell size h: distance() is exact up to h (any triangle
// nearer than h lies in the 27 cells around the point) and reports h beyond. It may stop early with
// any distance at or below `enough` (the caller only wants the largest of many minima).
class TriangleGrid {
public:
    TriangleGrid(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices, float h)
        : positions_(positions), indices_(indices), h_(h) {
        for (std::uint32_t t = 0; t + 2 < indices.size(); t += 3) {
            const glm::vec3 a = positions[indices[t]], b = positions[indices[t + 1]], c = positions[indices[t + 2]];
            const glm::ivec3 lo = cell(glm::min(a, glm::min(b, c))), hi = cell(glm::max(a, glm::max(b, c)));
            for (int z = lo.z; z <= hi.z; ++z)
                for (int y = lo.y; y <= hi.y; ++y)
                    for (int x = lo.x; x <= hi.x; ++x) cells_[key({x, y, z})].push_back(t);
        }
    }
    float distance(const glm::vec3& p, float enough) const {
        float best = h_;
        const glm::ivec3 c = cell(p);
        for (int n = 0; n < 27; ++n) {
            const int m = (n + 13) % 27;  // the point's own cell first
            const auto it = cells_.find(key(c + glm::ivec3(m % 3 - 1, (m / 3) % 3 - 1, m / 9 - 1)));
            if (it == cells_.end()) continue;
            for (std::uint32_t t : it->second) {
                const glm::vec3 q = closest_on_triangle(p, positions_[indices_[t]], positions_[indices_[t + 1]],
                                                        positions_[indices_[t + 2]]);
                best = std::min(best, glm::length(p - q));
                if (best <= enough) return best;
            }
        }
        return best;
    }

private:
    glm::ivec3 cell(const glm::vec3& p) const { return glm::ivec3(glm::floor(p / h_)); }
    static std::uint64_t key(const glm::ivec3& c) {
        return (std::uint64_t(std::uint32_t(c.x) & 0x1fffffu) << 42) |
               (std::uint64_t(std::uint32_t(c.y) & 0x1fffffu) << 21) | std::uint64_t(std::uint32_t(c.z) & 0x1fffffu);
    }
    std::span<const glm::vec3> positions_;
    std::span<const std::uint32_t> indices_;
    float h_;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

// Two-sided distance between the original surface and a simplified one, sampled: every original
// vertex (`original_vertices`, each once) to the simplified triangles, and every simplified
// triangle's centroid and edge midpoints to the original triangles (the simplified vertices are
// original vertices). `h` if any is beyond h. Both loops run on every core (TBB): they are most of
// a large model's load time.
float measured_error(std::span<const glm::vec3> positions, std::span<const std::uint32_t> original_vertices,
                     const TriangleGrid& original_grid, std::span<const std::uint32_t> simplified, float h) {
    const TriangleGrid simplified_grid(positions, simplified, h);
    const auto largest = [](float a, float b) { return std::max(a, b); };
    const float to_simplified = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, original_vertices.size(), 4096), 0.0f,
        [&](const tbb::blocked_range<std::size_t>& range, float worst) {
            for (std::size_t i = range.begin(); i != range.end(); ++i)
                worst = std::max(worst, simplified_grid.distance(positions[original_vertices[i]], worst));
            return worst;
        },
        largest);
    const float to_original = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, simplified.size() / 3, 2048), to_simplified,
        [&](const tbb::blocked_range<std::size_t>& range, float worst) {
            for (std::size_t t = range.begin(); t != range.end(); ++t) {
                const glm::vec3 a = positions[simplified[3 * t]], b = positions[simplified[3 * t + 1]],
                                c = positions[simplified[3 * t + 2]];
                for (const glm::vec3& sample : {(a + b + c) / 3.0f, 0.5f * (a + b), 0.5f * (b + c), 0.5f * (c + a)})
                    worst = std::max(worst, original_grid.distance(sample, worst));
            }
            return worst;
        },
        largest);
    return std::max(to_simplified, to_original);
}
}  // namespace

CasterLod build_caster_lod(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                           const std::function<void(double fraction)>& progress) {
    CasterLod lod;
    lod.indices.assign(indices.begin(), indices.end());
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
    const float reach = scale / 64.0f;  // errors up to 1/64 of the extent are measured exactly
    const TriangleGrid original_grid(positions, welded, reach);
    std::vector<std::uint32_t> original_vertices(welded.begin(), welded.end());
    std::sort(original_vertices.begin(), original_vertices.end());
    original_vertices.erase(std::unique(original_vertices.begin(), original_vertices.end()), original_vertices.end());

    // Each level is simplified from the last one kept, not from the original: the simplifier's cost
    // then shrinks with the levels instead of being the full mesh's 16 times over (most of the load
    // time of a large model). Its own error is then relative to that level, so the bound it gives is
    // the previous level's error plus it (triangle inequality); the measured one is still against
    // the original surface.
    std::vector<std::uint32_t> source = welded, out(indices.size());
    std::uint32_t previous_count = std::uint32_t(indices.size());
    float previous_error = 0.0f;
    constexpr int kTargets = 17;  // 1/8192 to 1/32 by sqrt(2)
    int tried = 0;
    for (float relative = 1.0f / 8192.0f; relative <= 1.0f / 32.0f; relative *= std::numbers::sqrt2_v<float>) {
        if (progress) progress(double(tried++) / kTargets);
        float result_error = 0.0f;
        // Target 0 triangles: the simplifier stops where the next collapse would exceed the error.
        const std::size_t count = meshopt_simplify(out.data(), source.data(), source.size(), xyz, positions.size(),
                                                   sizeof(glm::vec3), 0, relative, 0, &result_error);
        if (count == 0 || double(count) > 0.9 * double(previous_count)) continue;
        meshopt_optimizeVertexCache(out.data(), out.data(), count, positions.size());
        // meshoptimizer's error (relative to `scale`) measures the kept vertices against the original
        // faces' planes; the new, larger triangles sag further between their vertices (2.5 times it on
        // a finely tessellated sphere, more on thin spikes). So the distance between the two surfaces
        // is measured (sampled at vertices, centroids and edge midpoints) and the larger one kept.
        // Never a level finer than the one before.
        const std::span<const std::uint32_t> level(out.data(), count);
        const float measured = measured_error(positions, original_vertices, original_grid, level, reach);
        if (!(measured < reach)) break;  // beyond what the grid measures: coarser levels are useless
        const float error = std::max(measured, previous_error + result_error * scale);
        lod.levels.push_back({std::uint32_t(lod.indices.size()), std::uint32_t(count), error, is_closed(level)});
        lod.indices.insert(lod.indices.end(), out.begin(), out.begin() + std::ptrdiff_t(count));
        source.assign(out.begin(), out.begin() + std::ptrdiff_t(count));
        previous_count = std::uint32_t(count);
        previous_error = error;
    }
    if (progress) progress(1.0);
    return lod;
}

bool is_closed(std::span<const std::uint32_t> indices) {
    if (indices.empty() || indices.size() % 3 != 0) return false;
    std::unordered_map<std::uint64_t, int> directed;  // (a, b) -> occurrences
    directed.reserve(indices.size());
    auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
    for (std::size_t t = 0; t < indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = indices[t + std::size_t(e)], b = indices[t + std::size_t((e + 1) % 3)];
            if (a == b || ++directed[key(a, b)] > 1) return false;
        }
    for (const auto& [edge, count] : directed) {
        const auto reverse = directed.find(key(std::uint32_t(edge & 0xffffffffu), std::uint32_t(edge >> 32)));
        if (reverse == directed.end() || reverse->second != 1) return false;
    }
    return true;
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

}  // namespace envshadow::render
