#pragma once
// The map prefiltered for ratio shading (docs/DESIGN.md §4.1, §11): the Phong levels always, glTF's GGX levels
// when the scene has materials with metallic-roughness parameters. `render`, `bench` and the viewer make and
// upload them the same way.
#include <optional>

#include "env/compact_sources.h"
#include "env/environment.h"
#include "env/ggx_prefilter.h"
#include "env/importance.h"
#include "env/prefilter.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace envshadow::app {

struct PrefilteredMaps {
    PrefilteredEnvironment phong;
    std::optional<GgxPrefilteredEnvironment> ggx;  // of compact_sources.rest
    CompactSourceSplit compact_sources;            // with ggx: the map's suns, apart from the rest of it
};

// Whether any object's material has glTF's parameters (Material::metallic_roughness).
bool has_metallic_roughness(const Scene& scene);

// Both prefilterings over `hemisphere`, the GGX one only when `ggx`: of the map without its compact sources.
PrefilteredMaps prefilter_maps(const EnvironmentMap& map, Hemisphere hemisphere, bool ggx);

// Uploads the levels it holds (Renderer::set_prefiltered, set_ggx_prefiltered).
void upload(render::Renderer& renderer, const PrefilteredMaps& maps);

// One line per prefiltering: its levels, sizes, hemisphere and wall time.
void print_prefiltering(const PrefilteredMaps& maps, Hemisphere hemisphere);

}  // namespace envshadow::app
