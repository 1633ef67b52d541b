#pragma once
// Where each cell's depth map lives in the shadow atlas, and the orthographic projection that fills
// it (docs/DESIGN.md §5). Plain C++, no GL: tested headless.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "render/render_settings.h"

namespace envshadow::render {

// One tile of the atlas: its lower-left corner and side in atlas texels.
struct TileRect {
    int x = 0, y = 0, size = 0;
};

// Where the N tiles lie. Uniform: N square tiles of tile_size^2 texels in a grid of columns x rows;
// tile k at column k % columns, row k / columns (row 0 at the bottom, v = 0). Sized (TileSizing
// share or sqrt): power-of-two tiles of different sizes, at most tile_count * tile_size^2 texels in
// all, packed in Morton order (columns = rows = 0).
struct AtlasLayout {
    int tile_count = 0;
    int tile_size = 0;  // uniform: every tile's side; sized: the budget's side R
    int columns = 0;
    int rows = 0;
    int requested_tile_size = 0;  // differs from tile_size when the atlas had to shrink
    TileSizing sizing = TileSizing::uniform;
    int atlas_width = 0, atlas_height = 0;
    std::vector<TileRect> tiles;  // one per tile, in light order

    int width() const { return atlas_width; }
    int height() const { return atlas_height; }
    std::size_t bytes(int depth_bits) const {
        return std::size_t(width()) * std::size_t(height()) * std::size_t(depth_bits / 8);
    }
    // Texels of all tiles together (uniform: tile_count * tile_size^2).
    std::int64_t tile_texels() const;
    int smallest_tile() const;
    int largest_tile() const;
};

inline constexpr int kMinTileSize = 128;
inline constexpr int kMaxTileSize = 2048;
// Sized tiles span kMinTileSize..kMaxSizedTile (or up to the budget's R where R is larger).
inline constexpr int kMaxSizedTile = 1024;

// Columns are the power of two at or above sqrt(tiles) (128 tiles of 256^2: 16 x 8, 4096 x 2048).
// When the atlas would exceed `max_texture_size` (GL_MAX_TEXTURE_SIZE, GL_MAX_VIEWPORT_DIMS) the
// tile size is halved until it fits (requested_tile_size keeps the asked one, for a warning);
// throws PlatformError when even kMinTileSize does not fit.
AtlasLayout plan_atlas(int tiles, int tile_size, int max_texture_size);

// The weight a light's tile area follows: its luminance (share) or the luminance's square root
// (sqrt); uniform: 1.
double tile_weight(double luminance, TileSizing sizing);

// Power-of-two sides in min_size..max_size, one per weight, whose areas follow the weights (area_i
// near budget * w_i / sum w) with sum side_i^2 <= budget: the sides nearest (in log2) to the wanted
// ones, then halved (most over-served first) until within the budget, then doubled (most
// under-served first) while the budget allows. Lights of equal weight always get equal sides, and a
// heavier light never a smaller side than a lighter one. No positive weight: every weight 1.
// Needs budget >= weights.size() * min_size^2.
std::vector<int> choose_tile_sizes(std::span<const double> weights, std::int64_t budget, int min_size, int max_size);

// The atlas for lights of these luminances: uniform -> plan_atlas(luminance.size(), ...); share and
// sqrt -> choose_tile_sizes with the budget luminance.size() * tile_size^2, packed largest first in
// Morton order into a power-of-two-wide atlas (no gaps: each side divides every larger one). When
// the atlas would exceed `max_texture_size` the budget's side is halved until it fits (as
// plan_atlas); PlatformError when even kMinTileSize does not fit. No luminances: one tile.
AtlasLayout plan_atlas(std::span<const double> luminance, TileSizing sizing, int tile_size, int max_texture_size);

// Orthonormal frame of a directional light: `toward` points to the light (the cell centre w_i),
// the shadow map looks along -toward.
struct LightFrame {
    glm::vec3 right{1.0f, 0.0f, 0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    glm::vec3 toward{0.0f, 0.0f, 1.0f};
};
LightFrame light_frame(const glm::vec3& toward);

struct OrthographicFit {
    // World to the tile's clip cube [-1, 1]^3 (w = 1): x, y across the tile, z = -1 nearest the light.
    glm::mat4 clip_from_world{1.0f};
    float texel_world = 0.0f;  // world size of one texel (the larger of the two axes)
    float depth_range = 0.0f;  // world distance from clip z = -1 to +1
};

// Fits the projection tightly to `points` (the shadow casters' bounding-box corners) in the light's
// frame: tight in x, y and depth, then widened so the points stay `margin_texels` texels (of this
// tile's `tile_size`) inside its border (PCF taps never reach a neighbouring tile, receivers outside
// the casters read cleared depth) and 1% plus a little in depth (nothing is clipped at the near and
// far planes).
// No points: a unit box about the origin.
OrthographicFit fit_orthographic(const LightFrame& frame, std::span<const glm::vec3> points, int tile_size,
                                 float margin_texels);

}  // namespace envshadow::render
