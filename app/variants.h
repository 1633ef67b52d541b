#pragma once
// `bench --variants`: the grammar of the renderer variants measured side by side.
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
// the key a setting's name and the value as its option takes it (render::setting_table(); '_' in a key
// reads as '-'). Every variant validated. Empty text: one variant, `settings`. UsageError naming --variants.
std::vector<Variant> parse_variants(std::string_view text, const render::RenderSettings& settings);

// One variant of the grammar above applied to `settings`; UsageError in its own words.
render::RenderSettings apply_variant(render::RenderSettings settings, std::string_view variant);

// "caster-lod, depth-bits, ...": the keys, for help and messages.
std::string variant_keys();

}  // namespace envshadow::app
