#include "render/render_settings.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "core/error.h"
#include "render/shadow_atlas_layout.h"

namespace envshadow::render {

namespace {
template <typename Enum, std::size_t N>
Enum parse(const std::array<std::pair<Enum, std::string_view>, N>& names, std::string_view name) {
    std::string allowed;
    for (const auto& [value, text] : names) {
        if (text == name) return value;
        allowed += (allowed.empty() ? "" : ", ") + std::string(text);
    }
    throw UsageError("'" + std::string(name) + "' is not one of " + allowed);
}
template <typename Enum, std::size_t N>
std::string_view name_of(const std::array<std::pair<Enum, std::string_view>, N>& names, Enum value) {
    for (const auto& [v, text] : names)
        if (v == value) return text;
    return "?";
}
template <typename Enum, std::size_t N>
std::vector<std::string> names_in(const std::array<std::pair<Enum, std::string_view>, N>& names) {
    std::vector<std::string> out;
    for (const auto& [value, text] : names) out.emplace_back(text);
    return out;
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
constexpr std::array<std::pair<ShadingMode, std::string_view>, 2> kShadingModes{
    {{ShadingMode::cells, "cells"}, {ShadingMode::ratio, "ratio"}}};
constexpr std::array<std::pair<TileSizing, std::string_view>, 3> kTileSizings{
    {{TileSizing::uniform, "uniform"}, {TileSizing::share, "share"}, {TileSizing::sqrt_share, "sqrt"}}};

constexpr std::array<int, 4> kMsaaSampleCounts{1, 2, 4, 8};
constexpr std::array<std::pair<ShadowMode, std::string_view>, 2> kShadowModes{
    {{ShadowMode::hard, "hard"}, {ShadowMode::soft, "soft"}}};
constexpr std::array<std::pair<ShadowFit, std::string_view>, 2> kShadowFits{
    {{ShadowFit::frame, "frame"}, {ShadowFit::animation, "animation"}}};

constexpr std::array<OptimisationSwitch, 6> kSwitches = {{
    {"prepass", &RenderSettings::depth_prepass},
    {"ubo", &RenderSettings::lights_uniform_block},
    {"cull", &RenderSettings::cull_back_faces},
    {"specialise", &RenderSettings::specialise_shaders},
    {"tiles", &RenderSettings::shadow_tile_lists},
    {"flat", &RenderSettings::flat_receivers},
}};
}  // namespace

std::span<const int> msaa_sample_counts() {
    return kMsaaSampleCounts;
}

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
std::string_view to_string(ShadingMode mode) {
    return name_of(kShadingModes, mode);
}

std::string_view to_string(TileSizing sizing) {
    return name_of(kTileSizings, sizing);
}

std::string_view to_string(ShadowMode mode) {
    return name_of(kShadowModes, mode);
}

AtlasMode parse_atlas_mode(std::string_view name) {
    return parse(kAtlasModes, name);
}
PcfKernel parse_pcf_kernel(std::string_view name) {
    return parse(kPcfKernels, name);
}
SpecularMode parse_specular_mode(std::string_view name) {
    return parse(kSpecularModes, name);
}
CapKind parse_cap_kind(std::string_view name) {
    return parse(kCapKinds, name);
}
DiffuseMode parse_diffuse_mode(std::string_view name) {
    return parse(kDiffuseModes, name);
}
ShadingMode parse_shading_mode(std::string_view name) {
    return parse(kShadingModes, name);
}

TileSizing parse_tile_sizing(std::string_view name) {
    return parse(kTileSizings, name);
}

template <>
std::vector<std::string> names<AtlasMode>() {
    return names_in(kAtlasModes);
}
template <>
std::vector<std::string> names<PcfKernel>() {
    return names_in(kPcfKernels);
}
template <>
std::vector<std::string> names<SpecularMode>() {
    return names_in(kSpecularModes);
}
template <>
std::vector<std::string> names<CapKind>() {
    return names_in(kCapKinds);
}
template <>
std::vector<std::string> names<DiffuseMode>() {
    return names_in(kDiffuseModes);
}
template <>
std::vector<std::string> names<ShadingMode>() {
    return names_in(kShadingModes);
}
template <>
std::vector<std::string> names<TileSizing>() {
    return names_in(kTileSizings);
}
template <>
std::vector<std::string> names<ShadowMode>() {
    return names_in(kShadowModes);
}

ShadowMode parse_shadow_mode(std::string_view name) {
    return parse(kShadowModes, name);
}

std::string_view to_string(ShadowFit fit) {
    return name_of(kShadowFits, fit);
}
ShadowFit parse_shadow_fit(std::string_view name) {
    return parse(kShadowFits, name);
}
template <>
std::vector<std::string> names<ShadowFit>() {
    return names_in(kShadowFits);
}

void validate(const RenderSettings& settings) {
    if (settings.tile_size < kMinTileSize || settings.tile_size > kMaxTileSize)
        throw UsageError("shadow tile size " + std::to_string(settings.tile_size) + " is outside " +
                         std::to_string(kMinTileSize) + ".." + std::to_string(kMaxTileSize));
    if (settings.depth_bits != 16 && settings.depth_bits != 32)
        throw UsageError("shadow depth bits " + std::to_string(settings.depth_bits) + " is not 16 or 32");
    if (std::find(kMsaaSampleCounts.begin(), kMsaaSampleCounts.end(), settings.msaa) == kMsaaSampleCounts.end())
        throw UsageError("MSAA samples " + std::to_string(settings.msaa) + " is not 1, 2, 4 or 8");
    for (float bias : {settings.slope_bias, settings.normal_offset, settings.depth_bias})
        if (!std::isfinite(bias) || bias < 0.0f) throw UsageError("shadow biases must be finite and >= 0");
    if (!std::isfinite(settings.caster_lod) || settings.caster_lod < 0.0f || settings.caster_lod > kMaxCasterLod) {
        char text[96];
        std::snprintf(text, sizeof text, "caster LOD error %g is outside 0..%g shadow texels",
                      double(settings.caster_lod), double(kMaxCasterLod));
        throw UsageError(text);
    }
}

std::span<const OptimisationSwitch> optimisation_switches() {
    return kSwitches;
}

RenderSettings baseline(RenderSettings settings) {
    settings.caster_lod = 0.0f;
    for (const auto& [name, member] : kSwitches) settings.*member = false;
    settings.shadow_cache = false;
    settings.shadow_fit = ShadowFit::frame;
    return settings;
}

}  // namespace envshadow::render
