#pragma once
// A picture of a decomposition for people (like Fig. 2 of Barsi et al.): the map tone-mapped, cell
// borders drawn over it and a marker on every cell centre.
#include "core/image.h"
#include "env/cells.h"
#include "env/environment.h"

namespace envshadow {

// Exposure that brings the map's log-average luminance to middle grey (0.18), in stops.
float auto_exposure_stops(const EnvironmentMap& map);

// The map tone-mapped (auto_exposure_stops, filmic, sRGB), same size as the map.
Image8 draw_map(const EnvironmentMap& map);

// draw_map with the cells over it. Borders (between horizontally or vertically adjacent texels of different cells,
// across the u = 0/1 seam too) are drawn in white, centres as red dots with a dark outline.
Image8 draw_cells(const EnvironmentMap& map, const Decomposition& decomposition);

}  // namespace envshadow
