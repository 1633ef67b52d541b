#pragma once
// Nearest-site assignment of texels on the sphere (docs/DESIGN.md §3), the inner loop of every method.
// Site k's score at direction p is  p . s_k + bias_k;  a texel belongs to the site of highest score,
// the lowest index on ties. With zero biases that is the nearest site by angle; with bias_k = w_k / 2
// it is the nearest in the power distance |p - s_k|^2 - w_k = 2 - 2 p . s_k - w_k (CCVT's power diagram).
//
// Two implementations give the same assignment: the brute force (every site for every texel: the test
// oracle and the benchmark baseline) and a coarse-to-fine search over a quadtree of lat-long tiles,
// each bounded by a spherical cap, which keeps only the sites that can win somewhere in the tile. A tile
// left with one candidate is taken whole (its precomputed moments added at once).
#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <span>
#include <vector>

#include "env/importance.h"

namespace envshadow {

// Sums over the texels of one cell: what Lloyd and CCVT need to move a site and weigh a cell.
struct CellMoments {
    double importance = 0.0;                // sum of I
    glm::dvec3 importance_direction{0.0};   // sum of I w
    double solid_angle = 0.0;               // sum of dw
    glm::dvec3 solid_angle_direction{0.0};  // sum of dw w

    void add(double texel_importance, double texel_solid_angle, const glm::dvec3& direction) {
        importance += texel_importance;
        importance_direction += texel_importance * direction;
        solid_angle += texel_solid_angle;
        solid_angle_direction += texel_solid_angle * direction;
    }
    CellMoments& operator+=(const CellMoments& o) {
        importance += o.importance;
        importance_direction += o.importance_direction;
        solid_angle += o.solid_angle;
        solid_angle_direction += o.solid_angle_direction;
        return *this;
    }
};

// The cell's importance-weighted mean direction, normalised; the solid-angle-weighted one where the cell
// has no importance; `fallback` where that vanishes too (an empty cell, or one cell over a uniform sphere).
glm::dvec3 centroid_direction(const CellMoments& m, const glm::dvec3& fallback);

// `bias` is empty (all zero) or one per site. At most 65535 sites.
void assign_nearest_brute_force(const ImportanceMap& importance, std::span<const glm::dvec3> sites,
                                std::span<const double> bias, std::span<std::uint16_t> texel_cell);

// Moments of the cells of a given assignment.
std::vector<CellMoments> partition_moments(const ImportanceMap& importance, std::span<const std::uint16_t> texel_cell,
                                           int cell_count);

// The fast search. Holds the tile hierarchy of one importance map (which must outlive it). Results do
// not depend on the number of threads: work is split into fixed chunks and reduced in a fixed order.
class NearestSiteSearch {
public:
    explicit NearestSiteSearch(const ImportanceMap& importance);

    void assign(std::span<const glm::dvec3> sites, std::span<const double> bias,
                std::span<std::uint16_t> texel_cell) const;
    // partition_moments(assign(...)) without writing the assignment.
    std::vector<CellMoments> moments(std::span<const glm::dvec3> sites, std::span<const double> bias) const;

    struct Cap {  // bounding cap of a tile's texel centres
        glm::dvec3 centre{0.0, 1.0, 0.0};
        double cos_radius = -1.0, sin_radius = 0.0;
    };
    struct Level {
        int tile_size = 0;  // texels per side
        int columns = 0, rows = 0;
        // Below the chunk level, the tiles inside one chunk tile are stored together (block x block of
        // them), so that a chunk's descent stays in cache.
        int block = 1, block_columns = 0;
        std::vector<Cap> caps;             // per tile, at index(tx, ty); apart from the moments, which only
        std::vector<CellMoments> moments;  // tiles taken whole read
        std::size_t index(int tx, int ty) const {
            return (std::size_t(ty / block) * std::size_t(block_columns) + std::size_t(tx / block)) *
                       std::size_t(block * block) +
                   std::size_t(ty % block) * std::size_t(block) + std::size_t(tx % block);
        }
    };

private:
    const ImportanceMap* importance_;
    std::vector<Level> levels_;  // coarse to fine; each tile splits into 2 x 2 tiles of the next level
};

// How texels find their nearest site: the tile search, or every site for every texel (the baseline the
// benchmark compares against; both give the same cells).
enum class SiteSearch { tiles, brute_force };

// The nearest-site partition of one importance map (which must outlive it) by either search: what the
// relaxations evaluate at every iteration. The tile hierarchy is built on first use, so that a method
// that starts at a lower resolution (Lloyd) has freed that stage's memory by then: fresh pages are
// what a decomposition's first run in a process costs most (docs/PERFORMANCE.md, "Decomposition").
class Partition {
public:
    Partition(const ImportanceMap& importance, SiteSearch search);

    SiteSearch search() const { return search_; }
    std::vector<CellMoments> moments(std::span<const glm::dvec3> sites, std::span<const double> bias) const;
    void assign(std::span<const glm::dvec3> sites, std::span<const double> bias,
                std::span<std::uint16_t> texel_cell) const;

private:
    const NearestSiteSearch& tiles() const;

    const ImportanceMap* importance_;
    SiteSearch search_;
    mutable std::optional<NearestSiteSearch> tiles_;  // with SiteSearch::tiles, once used
};

}  // namespace envshadow
