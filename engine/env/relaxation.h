#pragma once
// What the relaxations (env/lloyd.cpp, env/ccvt.cpp) share; internal to them.
#include <memory>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "env/importance.h"
#include "env/nearest_site.h"

namespace envshadow::relaxation {

// The angle between two unit directions, accurate near 0 and pi.
double angle_between(const glm::dvec3& a, const glm::dvec3& b);

// A site whose cell holds no texel is moved next to the site of the cell with the largest
// importance x solid angle (the cell that most needs splitting), a quarter of that cell's radius away.
// Returns the largest jump, so that the relaxation goes on.
double reseed_empty_cells(std::vector<glm::dvec3>& sites, std::vector<double>* bias,
                          const std::vector<CellMoments>& cells);

// A copy of `importance` box-blurred over (2 radius + 1)^2 texels (wrapping around the seam, clamped at
// the poles) and scaled back to the same total: a smoother problem to start the capacity solve on.
ImportanceMap blurred(const ImportanceMap& importance, int radius);

// The problem at a coarser resolution, maybe blurred: its own importance map and partition.
struct Resolution {
    std::unique_ptr<ImportanceMap> importance;  // the partition keeps its address
    std::optional<Partition> partition;
};

// Whether the map can be taken to 1/factor of its resolution: factor divides it (the rows held and the
// whole map's) and leaves at least 16 rows.
bool coarsens(const ImportanceMap& fine, int factor);

// At full resolution where the map does not coarsen by `factor`.
Resolution at_resolution(const ImportanceMap& fine, int factor, int blur, SiteSearch search);

}  // namespace envshadow::relaxation
