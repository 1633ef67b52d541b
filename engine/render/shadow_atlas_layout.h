#pragma once
// Where each cell's depth map lives in the shadow atlas, and the orthographic projection that fills
// it (docs/DESIGN.md §5). Plain C++, no GL: tested headless.
#include <cstddef>
#include <span>
#include <string>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace envshadow::render {

// N square tiles of tile_size^2 texels in a grid of columns x rows; tile k at column k % columns,
// row k / columns (row 0 at the bottom, v = 0).
struct AtlasLayout {
    int tile_count = 0;
    int tile_size = 0;
    int columns = 0;
    int rows = 0;
    int requested_tile_size = 0;  // differs from tile_size when the atlas had to shrink

    int width() const { return columns * tile_size; }
    int height() const { return rows * tile_size; }
    std::size_t bytes(int depth_bits) const {
        return std::size_t(width()) * std::size_t(height()) * std::size_t(depth_bits / 8);
    }
};

inline constexpr int kMinTileSize = 128;
inline constexpr int kMaxTileSize = 2048;

// Columns are the power of two at or above sqrt(tiles) (128 tiles of 256^2: 16 x 8, 4096 x 2048).
// When the atlas would exceed `max_texture_size` (GL_MAX_TEXTURE_SIZE, GL_MAX_VIEWPORT_DIMS) the
// tile size is halved until it fits (requested_tile_size keeps the asked one, for a warning);
// throws PlatformError when even kMinTileSize does not fit.
AtlasLayout plan_atlas(int tiles, int tile_size, int max_texture_size);

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
// frame: tight in x, y and depth, then widened so the points stay `margin_texels` texels inside the
// tile's border (PCF taps never reach a neighbouring tile, receivers outside the casters read
// cleared depth) and 1% plus a little in depth (nothing is clipped at the near and far planes).
// No points: a unit box about the origin.
OrthographicFit fit_orthographic(const LightFrame& frame, std::span<const glm::vec3> points, int tile_size,
                                 float margin_texels);

}  // namespace envshadow::render
