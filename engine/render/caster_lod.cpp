#include "render/caster_lod.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <meshoptimizer.h>

namespace envshadow::render {

namespace {
constexpr float kErrorSafety = 3.0f;
}  // namespace

CasterLod build_caster_lod(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices) {
    CasterLod lod;
    lod.indices.assign(indices.begin(), indices.end());
    lod.levels.push_back({0u, std::uint32_t(indices.size()), 0.0f});
    if (indices.size() < 3 * 64 || positions.empty()) return lod;  // too small to be worth it

    const float* xyz = &positions[0].x;
    // Weld vertices that share a position (seams of normals or texture coordinates): a depth map only
    // sees positions, and the simplifier keeps every seam as a border otherwise.
    std::vector<std::uint32_t> welded(indices.size());
    meshopt_generateShadowIndexBuffer(welded.data(), indices.data(), indices.size(), xyz, positions.size(),
                                      sizeof(glm::vec3), sizeof(glm::vec3));
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
        lod.levels.push_back({std::uint32_t(lod.indices.size()), std::uint32_t(count), error});
        lod.indices.insert(lod.indices.end(), out.begin(), out.begin() + std::ptrdiff_t(count));
        previous_count = std::uint32_t(count);
        previous_error = error;
    }
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
    const float max_scale = std::max({glm::length(glm::vec3(world_from_object[0])),
                                      glm::length(glm::vec3(world_from_object[1])),
                                      glm::length(glm::vec3(world_from_object[2]))});
    if (!(max_scale > 0.0f) || !std::isfinite(max_scale)) return 0.0f;
    return fraction * min_texel_world / max_scale;
}

}  // namespace envshadow::render
