#pragma once
// Shadow-caster level of detail: a chain of simplified index buffers of a mesh
// (meshoptimizer), each with its geometric error, and the choice of the coarsest level whose error
// stays under a fraction of a shadow-map texel. Plain C++, no GL: tested headless.
//
// Why the image does not change: a caster's depth map is sampled at texel resolution; a surface
// that moves by at most `fraction` of a texel (in any direction: silhouette or depth) moves the
// sampled depth by less than the depth bias (1 texel) and the silhouette by less than the PCF
// footprint. The receivers are never simplified (shading draws the full mesh).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "scene/mesh_topology.h"  // is_closed

namespace envshadow::render {

struct CasterLevel {
    std::uint32_t first_index = 0;  // into CasterLod::indices (level 0: into the mesh's own indices)
    std::uint32_t index_count = 0;
    float error = 0.0f;   // bound on the distance (object space) of the simplified surface from the original
    bool closed = false;  // welded by position, every edge is shared by exactly two oppositely wound triangles
};

struct CasterLod {
    // Level 0 is the original index buffer (error 0), which is not copied here: a large mesh's index
    // buffer is a third of its memory. Levels 1, 2, ... are in `indices` (their first_index counts
    // from the start of it); each has fewer triangles and a larger error than the one before. All
    // levels index the mesh's own vertex array.
    std::vector<std::uint32_t> indices;
    std::vector<CasterLevel> levels;
};

// How a level is simplified from a large one. meshoptimizer's time per triangle grows with the size
// of one call (a large model's first level took most of its load time), so a level of more than
// `chunked_from` triangles is simplified in spatial chunks of about `chunk_triangles` (runs of the
// triangles' Morton order), on every core, each chunk's border locked so that the chunks still meet
// edge to edge; the seams, left at the finer level's resolution, go in the next level.
struct CasterLodChunks {
    std::size_t chunked_from = std::size_t(1) << 18;
    std::size_t chunk_triangles = std::size_t(1) << 17;
};

// Relative error targets (fractions of the mesh's extent) the chain is built for: 1/8192 growing by sqrt(2)
// up to 1/32. Levels that remove under 10% of the previous level's triangles are not kept.
// `progress`, if given, is called on the calling thread with the fraction of the work done so far
// (large models take seconds). Time and memory grow linearly with the triangles (docs/PERFORMANCE.md,
// "Large models").
CasterLod build_caster_lod(std::span<const glm::vec3> positions, std::span<const std::uint32_t> indices,
                           const std::function<void(double fraction)>& progress = {}, CasterLodChunks chunks = {});

// The coarsest level whose error is at most `max_error` (object space); level 0 when max_error <= 0.
int choose_caster_level(const CasterLod& lod, float max_error);

// Largest object-space error allowed for an instance drawn into tiles whose smallest texel is
// `min_texel_world` (world units): `fraction` of that texel divided by the largest column length of
// world_from_object (an object-space displacement e moves by at most e times it in the world).
// 0 (full resolution) when fraction <= 0, i.e. LOD off.
float caster_error_budget(const glm::mat4& world_from_object, float min_texel_world, float fraction);

// One instanced draw of a caster: `count` tiles at one level, their indices at
// CasterTiles::tiles[first ..].
struct CasterTileRun {
    int level = 0;
    std::uint32_t first = 0;
    std::uint32_t count = 0;
};

// A caster's draws into the atlas, one run per level.
struct CasterTiles {
    std::vector<std::int32_t> tiles;  // tile indices, grouped by level (ascending within a level)
    std::vector<CasterTileRun> runs;  // levels finest first
};

// Each tile at the coarsest level whose error is within `fraction` of that tile's own texel
// (`texel_world[k]`, world units): a small tile's texel is larger, so it takes a coarser level than a
// large tile of the same light frame. Appends to `out` (runs' `first` index out.tiles).
void append_caster_tiles(const CasterLod& lod, const glm::mat4& world_from_object, std::span<const float> texel_world,
                         float fraction, CasterTiles& out);

}  // namespace envshadow::render
