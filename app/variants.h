#pragma once
// `bench --variants`: the grammar of the renderer variants measured side by side, and the values of
// the optimisation flags (--caster-lod, --prepass) it shares with render.
#include <string>
#include <string_view>
#include <vector>

#include "render/render_settings.h"

namespace envshadow::app {

struct Variant {
    std::string label;  // the variant's text as given ("" without --variants)
    render::RenderSettings settings;
};

// `text`: variants separated by ';', each comma-separated items applied left to right to `settings`:
// a preset ("baseline": render::baseline(); "optimised" or "default": nothing changed) or key=value,
// with keys caster-lod (texels; "off" = 0), the switches of render::optimisation_switches() (on/off),
// depth-bits, tile, tile-sizes, atlas, pcf, shading, shadows, msaa, shadow-cache (on/off) and shadow-fit
// (animation/frame; both also spelt with '_'). Every variant validated. Empty text: one variant, `settings`.
// UsageError naming --variants.
std::vector<Variant> parse_variants(std::string_view text, const render::RenderSettings& settings);

// One variant of the grammar above applied to `settings`; UsageError in its own words.
render::RenderSettings apply_variant(render::RenderSettings settings, std::string_view variant);

// A caster LOD error: a number of shadow texels, or "off" (0); UsageError otherwise.
float parse_caster_lod(std::string_view text);
// "on" or "off"; UsageError otherwise.
bool parse_on_off(std::string_view text);

}  // namespace envshadow::app
