#include "render/shadow_atlas_layout.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "core/error.h"

namespace envshadow::render {

std::int64_t AtlasLayout::tile_texels() const {
    std::int64_t sum = 0;
    for (const TileRect& tile : tiles) sum += std::int64_t(tile.size) * tile.size;
    return sum;
}

int AtlasLayout::smallest_tile() const {
    int side = tiles.empty() ? 0 : tiles.front().size;
    for (const TileRect& tile : tiles) side = std::min(side, tile.size);
    return side;
}

int AtlasLayout::largest_tile() const {
    int side = 0;
    for (const TileRect& tile : tiles) side = std::max(side, tile.size);
    return side;
}

AtlasLayout plan_atlas(int tiles, int tile_size, int max_texture_size) {
    AtlasLayout layout;
    layout.tile_count = std::max(tiles, 1);
    layout.requested_tile_size = tile_size;
    layout.columns = 1;
    while (layout.columns * layout.columns < layout.tile_count) layout.columns *= 2;
    layout.rows = (layout.tile_count + layout.columns - 1) / layout.columns;
    layout.tile_size = tile_size;
    auto size_atlas = [&] {
        layout.atlas_width = layout.columns * layout.tile_size;
        layout.atlas_height = layout.rows * layout.tile_size;
    };
    size_atlas();
    while (layout.tile_size > kMinTileSize &&
           (layout.width() > max_texture_size || layout.height() > max_texture_size)) {
        layout.tile_size = std::max(kMinTileSize, layout.tile_size / 2);
        size_atlas();
    }
    if (layout.width() > max_texture_size || layout.height() > max_texture_size)
        throw PlatformError("shadow atlas of " + std::to_string(layout.tile_count) + " tiles of " +
                            std::to_string(layout.tile_size) + "^2 (" + std::to_string(layout.width()) + "x" +
                            std::to_string(layout.height()) + ") exceeds the GL limit of " +
                            std::to_string(max_texture_size));
    layout.tiles.resize(std::size_t(layout.tile_count));
    for (int k = 0; k < layout.tile_count; ++k)
        layout.tiles[std::size_t(k)] = {(k % layout.columns) * layout.tile_size,
                                        (k / layout.columns) * layout.tile_size, layout.tile_size};
    return layout;
}

double tile_weight(double luminance, TileSizing sizing) {
    const double positive = std::isfinite(luminance) ? std::max(luminance, 0.0) : 0.0;
    switch (sizing) {
        case TileSizing::share:
            return positive;
        case TileSizing::sqrt_share:
            return std::sqrt(positive);
        case TileSizing::uniform:
            break;
    }
    return 1.0;
}

namespace {
int log2_floor(std::int64_t value) {
    int exponent = 0;
    while ((std::int64_t(2) << exponent) <= value) ++exponent;
    return exponent;
}

// Texel (x, y) of Morton index `index`: x from the even bits, y from the odd ones.
TileRect morton_corner(std::int64_t index, int size) {
    TileRect rect;
    rect.size = size;
    for (int bit = 0; bit < 31; ++bit) {
        rect.x |= int((index >> (2 * bit)) & 1) << bit;
        rect.y |= int((index >> (2 * bit + 1)) & 1) << bit;
    }
    return rect;
}
}  // namespace

std::vector<int> choose_tile_sizes(std::span<const double> weights, std::int64_t budget, int min_size, int max_size) {
    const std::size_t n = weights.size();
    std::vector<int> sides(n, min_size);
    if (n == 0) return sides;
    std::vector<double> w(weights.begin(), weights.end());
    double sum = 0.0;
    for (double& v : w) {
        if (!std::isfinite(v) || v < 0.0) v = 0.0;
        sum += v;
    }
    if (!(sum > 0.0) || !std::isfinite(sum)) std::fill(w.begin(), w.end(), 1.0), sum = double(n);

    // Groups of equal weight, heaviest first: a group's tiles share one side, so equal lights get
    // equal tiles, and sides never increase from group to group.
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return w[a] > w[b]; });
    struct Group {
        double weight = 0.0;
        double wanted = 0.0;  // area per tile
        std::int64_t count = 0;
        int exponent = 0;
    };
    std::vector<Group> groups;
    for (std::size_t i : order) {
        if (groups.empty() || groups.back().weight != w[i]) groups.push_back({w[i], double(budget) * w[i] / sum, 0, 0});
        ++groups.back().count;
    }
    const int min_exponent = log2_floor(min_size), max_exponent = log2_floor(std::max(max_size, min_size));
    std::int64_t total = 0;
    for (Group& g : groups) {
        const double wanted_exponent = g.wanted > 0.0 ? 0.5 * std::log2(g.wanted) : double(min_exponent);
        g.exponent = std::clamp(int(std::lround(wanted_exponent)), min_exponent, max_exponent);
        total += g.count << (2 * g.exponent);
    }
    // Served: the tile's area over the wanted one (a weightless tile is always over-served).
    auto served = [](const Group& g) {
        const double area = std::ldexp(1.0, 2 * g.exponent);
        return g.wanted > 0.0 ? area / g.wanted : std::numeric_limits<double>::infinity();
    };
    while (total > budget) {
        std::size_t pick = groups.size();
        for (std::size_t j = 0; j < groups.size(); ++j) {
            const bool monotone = j + 1 == groups.size() || groups[j].exponent > groups[j + 1].exponent;
            if (groups[j].exponent > min_exponent && monotone &&
                (pick == groups.size() || served(groups[j]) >= served(groups[pick])))
                pick = j;
        }
        if (pick == groups.size()) break;  // every tile at min_size: the budget was too small
        Group& g = groups[pick];
        total -= 3 * (g.count << (2 * (g.exponent - 1)));
        --g.exponent;
    }
    for (;;) {
        std::size_t pick = groups.size();
        for (std::size_t j = 0; j < groups.size(); ++j) {
            const Group& g = groups[j];
            const bool monotone = j == 0 || groups[j - 1].exponent > g.exponent;
            const std::int64_t growth = 3 * (g.count << (2 * g.exponent));
            if (g.exponent < max_exponent && monotone && total + growth <= budget &&
                (pick == groups.size() || served(g) < served(groups[pick])))
                pick = j;
        }
        if (pick == groups.size()) break;
        Group& g = groups[pick];
        total += 3 * (g.count << (2 * g.exponent));
        ++g.exponent;
    }
    std::size_t next = 0;
    for (const Group& g : groups)
        for (std::int64_t c = 0; c < g.count; ++c) sides[order[next++]] = 1 << g.exponent;
    return sides;
}

AtlasLayout plan_atlas(std::span<const double> luminance, TileSizing sizing, int tile_size, int max_texture_size) {
    const int tiles = std::max(int(luminance.size()), 1);
    if (sizing == TileSizing::uniform) return plan_atlas(tiles, tile_size, max_texture_size);
    std::vector<double> weights(std::size_t(tiles), 1.0);
    for (std::size_t k = 0; k < luminance.size(); ++k) weights[k] = tile_weight(luminance[k], sizing);

    AtlasLayout layout;
    layout.tile_count = tiles;
    layout.requested_tile_size = tile_size;
    layout.sizing = sizing;
    const int largest_side = 1 << log2_floor(std::max(tile_size, kMaxSizedTile));
    for (layout.tile_size = tile_size;; layout.tile_size = std::max(kMinTileSize, layout.tile_size / 2)) {
        const std::int64_t budget = std::int64_t(tiles) * layout.tile_size * layout.tile_size;
        const int max_side = std::max(kMinTileSize, std::min(largest_side, 1 << log2_floor(max_texture_size)));
        const std::vector<int> sides = choose_tile_sizes(weights, budget, kMinTileSize, max_side);
        // Largest first, each at the Morton index of the area before it: that index is a multiple of
        // its side squared (every earlier side is a multiple of it), so it starts an aligned square.
        std::vector<std::size_t> order(sides.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return sides[a] > sides[b]; });
        std::int64_t area = 0;
        for (int side : sides) area += std::int64_t(side) * side;
        int width = sides[order.front()];
        while (std::int64_t(width) * width < area) width *= 2;
        layout.tiles.assign(sides.size(), TileRect{});
        layout.atlas_width = width;
        layout.atlas_height = 0;
        std::int64_t index = 0;
        for (std::size_t k : order) {
            layout.tiles[k] = morton_corner(index, sides[k]);
            layout.atlas_height = std::max(layout.atlas_height, layout.tiles[k].y + sides[k]);
            index += std::int64_t(sides[k]) * sides[k];
        }
        if (layout.width() <= max_texture_size && layout.height() <= max_texture_size) return layout;
        if (layout.tile_size == kMinTileSize)
            throw PlatformError("shadow atlas of " + std::to_string(tiles) + " tiles in a budget of " +
                                std::to_string(tiles) + " x " + std::to_string(layout.tile_size) + "^2 texels (" +
                                std::to_string(layout.width()) + "x" + std::to_string(layout.height()) +
                                ") exceeds the GL limit of " + std::to_string(max_texture_size));
    }
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
