#include "render/shadow_atlas_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "core/error.h"

namespace envshadow::render {

AtlasLayout plan_atlas(int tiles, int tile_size, int max_texture_size) {
    AtlasLayout layout;
    layout.tile_count = std::max(tiles, 1);
    layout.requested_tile_size = tile_size;
    layout.columns = 1;
    while (layout.columns * layout.columns < layout.tile_count) layout.columns *= 2;
    layout.rows = (layout.tile_count + layout.columns - 1) / layout.columns;
    layout.tile_size = tile_size;
    while (layout.tile_size > kMinTileSize && (layout.width() > max_texture_size || layout.height() > max_texture_size))
        layout.tile_size = std::max(kMinTileSize, layout.tile_size / 2);
    if (layout.width() > max_texture_size || layout.height() > max_texture_size)
        throw PlatformError("shadow atlas of " + std::to_string(layout.tile_count) + " tiles of " +
                            std::to_string(layout.tile_size) + "^2 (" + std::to_string(layout.width()) + "x" +
                            std::to_string(layout.height()) + ") exceeds the GL limit of " +
                            std::to_string(max_texture_size));
    return layout;
}

LightFrame light_frame(const glm::vec3& toward) {
    LightFrame frame;
    frame.toward = glm::normalize(toward);
    // Any up not parallel to the light; +Y unless the light is near the zenith or nadir.
    const glm::vec3 helper = std::abs(frame.toward.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    frame.right = glm::normalize(glm::cross(helper, frame.toward));
    frame.up = glm::cross(frame.toward, frame.right);
    return frame;
}

OrthographicFit fit_orthographic(const LightFrame& frame, std::span<const glm::vec3> points, int tile_size,
                                 float margin_texels) {
    constexpr float inf = std::numeric_limits<float>::infinity();
    glm::vec3 lo(inf), hi(-inf);  // (right, up, toward) coordinates
    for (const glm::vec3& p : points) {
        const glm::vec3 l(glm::dot(p, frame.right), glm::dot(p, frame.up), glm::dot(p, frame.toward));
        lo = glm::min(lo, l);
        hi = glm::max(hi, l);
    }
    if (points.empty()) lo = glm::vec3(-1.0f), hi = glm::vec3(1.0f);

    // A flat caster seen edge-on has no extent along one axis: keep the box from collapsing.
    const glm::vec3 extent = hi - lo;
    const float floor = std::max(1e-3f * std::max({extent.x, extent.y, extent.z}), 1e-6f);
    glm::vec3 half = 0.5f * glm::max(extent, glm::vec3(floor));
    const glm::vec3 centre = 0.5f * (lo + hi);
    // The points span tile_size - 2 margin texels of the tile.
    const float widen = float(tile_size) / std::max(float(tile_size) - 2.0f * margin_texels, 1.0f);
    half.x *= widen;
    half.y *= widen;
    half.z = half.z * 1.01f + floor;

    // x_clip = (right.p - centre.x) / half.x, likewise y; z_clip = (centre.z - toward.p) / half.z so
    // that the point nearest the light has the smallest depth.
    glm::mat4 m(0.0f);  // column-major: m[column][row]
    for (int c = 0; c < 3; ++c) {
        m[c][0] = frame.right[c] / half.x;
        m[c][1] = frame.up[c] / half.y;
        m[c][2] = -frame.toward[c] / half.z;
    }
    m[3] = glm::vec4(-centre.x / half.x, -centre.y / half.y, centre.z / half.z, 1.0f);

    OrthographicFit fit;
    fit.clip_from_world = m;
    fit.texel_world = 2.0f * std::max(half.x, half.y) / float(tile_size);
    fit.depth_range = 2.0f * half.z;
    return fit;
}

}  // namespace envshadow::render
