#include "prefiltering.h"

#include <algorithm>
#include <cstdio>

#include "options.h"

namespace envshadow::app {

bool has_metallic_roughness(const Scene& scene) {
    return std::ranges::any_of(scene.objects,
                               [](const Object& o) { return o.material.metallic_roughness.has_value(); });
}

PrefilteredMaps prefilter_maps(const EnvironmentMap& map, Hemisphere hemisphere, bool ggx) {
    PrefilteredMaps maps{prefilter_environment(map, hemisphere), std::nullopt, {}};
    if (ggx) {
        maps.compact_sources = split_compact_sources(map, hemisphere);
        maps.ggx = prefilter_environment_ggx(maps.compact_sources.rest, hemisphere);
    }
    return maps;
}

void upload(render::Renderer& renderer, const PrefilteredMaps& maps) {
    renderer.set_prefiltered(maps.phong);
    if (maps.ggx) renderer.set_ggx_prefiltered(*maps.ggx, maps.compact_sources);
}

void print_prefiltering(const PrefilteredMaps& maps, Hemisphere hemisphere) {
    const auto& phong = maps.phong.levels;
    std::printf("prefiltered: %zu levels n = 1..%g, %dx%d to %dx%d, %s, %.3f s\n", phong.size(),
                double(phong.back().shininess), phong.front().width, phong.front().height, phong.back().width,
                phong.back().height, hemisphere_words(hemisphere), maps.phong.seconds);
    if (!maps.ggx) return;
    const auto& ggx = maps.ggx->levels;
    std::printf("prefiltered for glTF's BRDF: %zu levels roughness %g..%g, %dx%d to %dx%d, %.3f s\n", ggx.size(),
                double(ggx.front().roughness), double(ggx.back().roughness), ggx.front().width, ggx.front().height,
                ggx.back().width, ggx.back().height, maps.ggx->seconds);
}

}  // namespace envshadow::app
