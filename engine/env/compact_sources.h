#pragma once
// The map's compact sources (a sun): small, bright regions taken out of the map that glTF's split sum looks up,
// so that their reflection is drawn once, with the BRDF's own lobe (docs/DESIGN.md §11, "Compact sources").
#include <vector>

#include <glm/vec3.hpp>

#include "env/environment.h"
#include "env/importance.h"

namespace envshadow {

// A texel is part of a source where its luminance is above kCompactRadianceFactor times the map's mean
// radiance over the hemisphere; a source is a 4-connected region of such texels (wrapping in u) whose spread
// about its centre, weighted by the excess over the threshold, is at most kMaxCompactSourceRadiusDegrees. At
// most kMaxCompactSources, those of most power. A source takes its texels whole (what the split sum kept of a
// sun, a plateau at the threshold, is sharper than its round lobe renders well); its centre is that light's,
// its cap the excess's spread about it, the part that makes it compact.
inline constexpr double kCompactRadianceFactor = 4.0;
inline constexpr double kMaxCompactSourceRadiusDegrees = 5.0;
inline constexpr int kMaxCompactSources = 4;  // GLSL's u_compact_directions[MAX_COMPACT_SOURCES]

struct CompactSource {
    glm::vec3 direction{0.0f, 1.0f, 0.0f};  // map space, unit: the luminance-weighted centre
    float cos_radius = 1.0f;                // of the cap with the same mean cosine about it (Cell's weighted cap)
    glm::vec3 radiance{0.0f};               // integral of its texels' L dw (RGB)
};

struct CompactSourceSplit {
    EnvironmentMap rest;                 // the map with each source's texels black
    std::vector<CompactSource> sources;  // brightest first
};

// rest's integral of L dw plus the sources' radiance is the map's, within rounding. A map without a texel
// above the threshold (or black) has none and rest is the map.
CompactSourceSplit split_compact_sources(const EnvironmentMap& map, Hemisphere hemisphere);

}  // namespace envshadow
