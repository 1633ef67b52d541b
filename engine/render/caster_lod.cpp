#include "render/caster_lod.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <meshoptimizer.h>

namespace envshadow::render {

namespace {
constexpr float kErrorSafety = 3.0f;
}  // namespace

CasterLod build_caster_lod(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices) {
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

    std::vector<std::uint32_t> out(indices.size());
    std::uint32_t previous_count = std::uint32_t(indices.size());
    float previous_error = 0.0f;
    for (float relative = 1.0f / 8192.0f; relative <= 1.0f / 32.0f; relative *= std::numbers::sqrt2_v<float>) {
        float result_error = 0.0f;
        // Target 0 triangles: the simplifier stops where the next collapse would exceed the error.
        const std::size_t count = meshopt_simplify(out.data(), welded.data(), welded.size(), xyz, positions.size(),
                                                   sizeof(glm::vec3), 0, relative, 0, &result_error);
        if (count == 0 || double(count) > 0.9 * double(previous_count)) continue;
        meshopt_optimizeVertexCache(out.data(), out.data(), count, positions.size());
        // meshoptimizer's error is relative to `scale` and measures the kept vertices against the
        // original faces' planes; the new, larger triangles sag further between their vertices (on a
        // finely tessellated sphere the true distance reaches 2.5 times it at the finest level:
        // tests/render/caster_lod_test.cpp), so the level is stored with three times it. Never a level
        // finer than the one before.
        const float error = std::max(kErrorSafety * result_error * scale, previous_error);
        lod.levels.push_back({std::uint32_t(lod.indices.size()), std::uint32_t(count), error,
                              is_closed(std::span<const std::uint32_t>(out.data(), count))});
        lod.indices.insert(lod.indices.end(), out.begin(), out.begin() + std::ptrdiff_t(count));
        previous_count = std::uint32_t(count);
        previous_error = error;
    }
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
    const float max_scale = std::max({glm::length(glm::vec3(world_from_object[0])),
                                      glm::length(glm::vec3(world_from_object[1])),
                                      glm::length(glm::vec3(world_from_object[2]))});
    if (!(max_scale > 0.0f) || !std::isfinite(max_scale)) return 0.0f;
    return fraction * min_texel_world / max_scale;
}

}  // namespace envshadow::render
