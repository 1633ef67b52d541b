#include "variants.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/error.h"
#include "options.h"

namespace envshadow::app {
namespace {

std::string_view trim(std::string_view text) {
    while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
    while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
    return text;
}

double parse_number(std::string_view text) {
    const std::string copy(text);
    char* end = nullptr;
    const double value = std::strtod(copy.c_str(), &end);
    if (copy.empty() || end != copy.c_str() + copy.size() || !std::isfinite(value))
        throw UsageError("'" + copy + "' is not a number");
    return value;
}

// The pieces of `text` between `separator`s, in order (empty pieces kept).
std::vector<std::string_view> split(std::string_view text, char separator) {
    std::vector<std::string_view> pieces;
    for (std::size_t start = 0; start <= text.size();) {
        const std::size_t end = std::min(text.find(separator, start), text.size());
        pieces.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return pieces;
}

}  // namespace

float parse_caster_lod(std::string_view text) {
    return text == "off" ? 0.0f : float(parse_number(text));
}

bool parse_on_off(std::string_view text) {
    if (text == "on") return true;
    if (text == "off") return false;
    throw UsageError("'" + std::string(text) + "' is not on or off");
}

render::RenderSettings apply_variant(render::RenderSettings settings, std::string_view variant) {
    const std::span<const render::OptimisationSwitch> switches = render::optimisation_switches();
    for (std::string_view piece : split(variant, ',')) {
        const std::string_view item = trim(piece);
        if (item.empty() || item == "optimised" || item == "default") continue;
        if (item == "baseline") {
            settings = render::baseline(settings);
            continue;
        }
        const std::size_t eq = item.find('=');
        if (eq == std::string_view::npos)
            throw UsageError("'" + std::string(item) + "' is neither baseline, optimised nor key=value");
        const std::string_view key = trim(item.substr(0, eq)), value = trim(item.substr(eq + 1));
        const auto on_off =
            std::find_if(switches.begin(), switches.end(), [&](const auto& s) { return s.name == key; });
        if (on_off != switches.end()) {
            settings.*(on_off->member) = parse_on_off(value);
        } else if (key == "caster-lod") {
            settings.caster_lod = parse_caster_lod(value);
        } else if (key == "depth-bits") {
            settings.depth_bits = int(parse_number(value));
        } else if (key == "tile") {
            settings.tile_size = int(parse_number(value));
        } else if (key == "tile-sizes") {
            settings.tile_sizing = render::parse_tile_sizing(value);
        } else if (key == "atlas") {
            settings.atlas = render::parse_atlas_mode(value);
        } else if (key == "pcf") {
            settings.pcf = render::parse_pcf_kernel(value);
        } else if (key == "shading") {
            settings.shading = render::parse_shading_mode(value);
        } else if (key == "msaa") {
            settings.msaa = int(parse_number(value));
        } else if (key == "shadows") {
            settings.shadows = render::parse_shadow_mode(value);
        } else if (key == "shadow-cache" || key == "shadow_cache") {
            settings.shadow_cache = parse_on_off(value);
        } else if (key == "shadow-fit" || key == "shadow_fit") {
            settings.shadow_fit = render::parse_shadow_fit(value);
        } else {
            std::string keys = "caster-lod";
            for (const render::OptimisationSwitch& s : switches) keys += ", " + std::string(s.name);
            throw UsageError(
                "unknown key '" + std::string(key) + "' (" + keys +
                ", depth-bits, tile, atlas, pcf, shading, shadows, tile-sizes, msaa, shadow-cache, shadow-fit)");
        }
    }
    render::validate(settings);
    return settings;
}

std::vector<Variant> parse_variants(std::string_view text, const render::RenderSettings& settings) {
    if (text.empty()) return {Variant{"", settings}};
    std::vector<Variant> variants;
    for (std::string_view label : split(text, ';'))
        variants.push_back(
            {std::string(label), naming_flag("--variants", [&] { return apply_variant(settings, label); })});
    return variants;
}

}  // namespace envshadow::app
