#include "render/render_settings.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <string>
#include <utility>

#include "core/error.h"
#include "render/shadow_atlas_layout.h"

namespace envshadow::render {

namespace {
template <typename Enum, std::size_t N>
Enum parse(const std::array<std::pair<Enum, std::string_view>, N>& names, std::string_view name,
           std::string_view option) {
    std::string allowed;
    for (const auto& [value, text] : names) {
        if (text == name) return value;
        allowed += (allowed.empty() ? "" : ", ") + std::string(text);
    }
    throw UsageError(std::string(option) + ": '" + std::string(name) + "' is not one of " + allowed);
}
template <typename Enum, std::size_t N>
std::string_view name_of(const std::array<std::pair<Enum, std::string_view>, N>& names, Enum value) {
    for (const auto& [v, text] : names)
        if (v == value) return text;
    return "?";
}

constexpr std::array<std::pair<AtlasMode, std::string_view>, 3> kAtlasModes{
    {{AtlasMode::clip_distances, "clip-distances"},
     {AtlasMode::viewport_array, "viewport-array"},
     {AtlasMode::per_tile, "per-tile"}}};
constexpr std::array<std::pair<PcfKernel, std::string_view>, 2> kPcfKernels{
    {{PcfKernel::hardware_2x2, "2x2"}, {PcfKernel::wide, "wide"}}};
constexpr std::array<std::pair<SpecularMode, std::string_view>, 2> kSpecularModes{
    {{SpecularMode::blended, "blended"}, {SpecularMode::single, "single"}}};
constexpr std::array<std::pair<CapKind, std::string_view>, 2> kCapKinds{
    {{CapKind::solid_angle, "solid-angle"}, {CapKind::weighted, "weighted"}}};
constexpr std::array<std::pair<DiffuseMode, std::string_view>, 2> kDiffuseModes{
    {{DiffuseMode::center, "center"}, {DiffuseMode::cap, "cap"}}};
}  // namespace

std::string_view to_string(AtlasMode mode) {
    return name_of(kAtlasModes, mode);
}
std::string_view to_string(PcfKernel kernel) {
    return name_of(kPcfKernels, kernel);
}
std::string_view to_string(SpecularMode mode) {
    return name_of(kSpecularModes, mode);
}
std::string_view to_string(CapKind kind) {
    return name_of(kCapKinds, kind);
}
std::string_view to_string(DiffuseMode mode) {
    return name_of(kDiffuseModes, mode);
}

AtlasMode parse_atlas_mode(std::string_view name, std::string_view option) {
    return parse(kAtlasModes, name, option);
}
PcfKernel parse_pcf_kernel(std::string_view name, std::string_view option) {
    return parse(kPcfKernels, name, option);
}
SpecularMode parse_specular_mode(std::string_view name, std::string_view option) {
    return parse(kSpecularModes, name, option);
}
CapKind parse_cap_kind(std::string_view name, std::string_view option) {
    return parse(kCapKinds, name, option);
}
DiffuseMode parse_diffuse_mode(std::string_view name, std::string_view option) {
    return parse(kDiffuseModes, name, option);
}

void validate(const RenderSettings& settings) {
    if (settings.tile_size < kMinTileSize || settings.tile_size > kMaxTileSize)
        throw UsageError("--tile: " + std::to_string(settings.tile_size) + " is outside " +
                         std::to_string(kMinTileSize) + ".." + std::to_string(kMaxTileSize));
    if (settings.depth_bits != 16 && settings.depth_bits != 32)
        throw UsageError("--depth-bits: " + std::to_string(settings.depth_bits) + " is not 16 or 32");
    for (float bias : {settings.slope_bias, settings.normal_offset, settings.depth_bias})
        if (!std::isfinite(bias) || bias < 0.0f) throw UsageError("shadow biases must be finite and >= 0");
    if (!std::isfinite(settings.caster_lod) || settings.caster_lod < 0.0f || settings.caster_lod > 4.0f)
        throw UsageError("--caster-lod: the error must be 0..4 shadow texels");
}

namespace {
std::string_view trim(std::string_view text) {
    while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
    while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
    return text;
}

double parse_number(std::string_view text, std::string_view option) {
    const std::string copy(text);
    char* end = nullptr;
    const double value = std::strtod(copy.c_str(), &end);
    if (copy.empty() || end != copy.c_str() + copy.size() || !std::isfinite(value))
        throw UsageError(std::string(option) + ": '" + copy + "' is not a number");
    return value;
}

bool parse_on_off(std::string_view text, std::string_view option) {
    if (text == "on") return true;
    if (text == "off") return false;
    throw UsageError(std::string(option) + ": '" + std::string(text) + "' is not on or off");
}
}  // namespace

namespace {
// The on/off optimisations of issue 10, by their --variants key; baseline() turns them all off
// (caster-lod, the eighth, takes a number).
constexpr std::array<std::pair<std::string_view, bool RenderSettings::*>, 6> kSwitches = {{
    {"prepass", &RenderSettings::depth_prepass},
    {"ubo", &RenderSettings::lights_uniform_block},
    {"cull", &RenderSettings::cull_back_faces},
    {"specialise", &RenderSettings::specialise_shaders},
    {"tiles", &RenderSettings::shadow_tile_lists},
    {"flat", &RenderSettings::flat_receivers},
}};
}  // namespace

RenderSettings apply_variant(RenderSettings settings, std::string_view variant, std::string_view option) {
    std::size_t start = 0;
    while (start <= variant.size()) {
        const std::size_t comma = std::min(variant.find(',', start), variant.size());
        const std::string_view item = trim(variant.substr(start, comma - start));
        start = comma + 1;
        if (item.empty()) continue;
        if (item == "baseline") {
            settings = baseline(settings);
            continue;
        }
        if (item == "optimised" || item == "default") continue;
        const std::size_t eq = item.find('=');
        if (eq == std::string_view::npos)
            throw UsageError(std::string(option) + ": '" + std::string(item) +
                             "' is neither baseline, optimised nor key=value");
        const std::string_view key = trim(item.substr(0, eq)), value = trim(item.substr(eq + 1));
        const auto on_off =
            std::find_if(kSwitches.begin(), kSwitches.end(), [&](const auto& s) { return s.first == key; });
        if (on_off != kSwitches.end()) {
            settings.*(on_off->second) = parse_on_off(value, option);
        } else if (key == "caster-lod") {
            settings.caster_lod = value == "off" ? 0.0f : float(parse_number(value, option));
        } else if (key == "depth-bits") {
            settings.depth_bits = int(parse_number(value, option));
        } else if (key == "tile") {
            settings.tile_size = int(parse_number(value, option));
        } else if (key == "atlas") {
            settings.atlas = parse_atlas_mode(value, option);
        } else if (key == "pcf") {
            settings.pcf = parse_pcf_kernel(value, option);
        } else {
            std::string keys = "caster-lod";
            for (const auto& [name, member] : kSwitches) keys += ", " + std::string(name);
            throw UsageError(std::string(option) + ": unknown key '" + std::string(key) + "' (" + keys +
                             ", depth-bits, tile, atlas, pcf)");
        }
    }
    validate(settings);
    return settings;
}

RenderSettings baseline(RenderSettings settings) {
    settings.caster_lod = 0.0f;
    for (const auto& [name, member] : kSwitches) settings.*member = false;
    return settings;
}

}  // namespace envshadow::render
