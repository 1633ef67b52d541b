#include "render/render_settings.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"
#include "render/shadow_atlas_layout.h"

namespace envshadow::render {

namespace {

constexpr std::array<int, 4> kMsaaSampleCounts{1, 2, 4, 8};
constexpr double kUnbounded = std::numeric_limits<double>::infinity();

// Shortest text that reads back to the same value: "0.3", "256".
template <typename Number>
std::string shortest(Number value) {
    std::array<char, 32> text{};
    const auto [end, error] = std::to_chars(text.data(), text.data() + text.size(), value);
    return std::string(text.data(), end);
}

// "a, b or c".
std::string either(const std::vector<std::string>& values) {
    std::string text;
    for (std::size_t i = 0; i < values.size(); ++i)
        text += (i == 0 ? "" : i + 1 == values.size() ? " or " : ", ") + values[i];
    return text;
}

template <typename Number>
Number parse_number(std::string_view text) {
    Number value{};
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc() || end != text.data() + text.size() || !std::isfinite(double(value)))
        throw UsageError("'" + std::string(text) + "' is not a number");
    return value;
}

template <NamedEnum Enum>
SettingInfo choice(std::string_view name, Enum RenderSettings::*member, SettingEffect effect, std::string_view help) {
    return {.name = name,
            .help = help,
            .kind = SettingKind::choice,
            .effect = effect,
            .choices = enum_value_names<Enum>(),
            .parse = [member](RenderSettings& s, std::string_view text) { s.*member = parse_enum<Enum>(text); },
            .format = [member](const RenderSettings& s) { return std::string(to_string(s.*member)); },
            .check = [](const RenderSettings&) {}};
}

SettingInfo on_off(std::string_view name, bool RenderSettings::*member, SettingEffect effect, std::string_view help) {
    return {.name = name,
            .help = help,
            .kind = SettingKind::on_off,
            .effect = effect,
            .choices = {"on", "off"},
            .parse =
                [member](RenderSettings& s, std::string_view text) {
                    if (text != "on" && text != "off") throw UsageError("'" + std::string(text) + "' is not on or off");
                    s.*member = text == "on";
                },
            .format = [member](const RenderSettings& s) { return std::string(s.*member ? "on" : "off"); },
            .check = [](const RenderSettings&) {}};
}

// An integer that is one of `allowed`; `what` names it in messages ("shadow depth bits").
SettingInfo integer_of(std::string_view name, int RenderSettings::*member, std::span<const int> allowed,
                       std::string_view what, SettingEffect effect, std::string_view help) {
    std::vector<std::string> choices;
    for (int value : allowed) choices.push_back(std::to_string(value));
    return {.name = name,
            .help = help,
            .kind = SettingKind::integer,
            .effect = effect,
            .choices = choices,
            .parse = [member](RenderSettings& s, std::string_view text) { s.*member = parse_number<int>(text); },
            .format = [member](const RenderSettings& s) { return std::to_string(s.*member); },
            .check =
                [member, choices, what = std::string(what)](const RenderSettings& s) {
                    const std::string value = std::to_string(s.*member);
                    if (std::find(choices.begin(), choices.end(), value) == choices.end())
                        throw UsageError(what + " " + value + " is not " + either(choices));
                }};
}

SettingInfo integer_in(std::string_view name, int RenderSettings::*member, int min, int max, std::string_view what,
                       SettingEffect effect, std::string_view help) {
    return {.name = name,
            .help = help,
            .kind = SettingKind::integer,
            .effect = effect,
            .choices = {},
            .min = double(min),
            .max = double(max),
            .parse = [member](RenderSettings& s, std::string_view text) { s.*member = parse_number<int>(text); },
            .format = [member](const RenderSettings& s) { return std::to_string(s.*member); },
            .check =
                [member, min, max, what = std::string(what)](const RenderSettings& s) {
                    if (s.*member < min || s.*member > max)
                        throw UsageError(what + " " + std::to_string(s.*member) + " is outside " + std::to_string(min) +
                                         ".." + std::to_string(max));
                }};
}

// A finite number within min..max (max may be kUnbounded); `unit` ends the range message.
SettingInfo number_in(std::string_view name, float RenderSettings::*member, double min, double max,
                      std::string_view what, std::string_view unit, SettingEffect effect, std::string_view help) {
    return {.name = name,
            .help = help,
            .kind = SettingKind::number,
            .effect = effect,
            .choices = {},
            .min = min,
            .max = max,
            .parse = [member](RenderSettings& s, std::string_view text) { s.*member = parse_number<float>(text); },
            .format = [member](const RenderSettings& s) { return shortest(s.*member); },
            .check =
                [member, min, max, what = std::string(what), unit = std::string(unit)](const RenderSettings& s) {
                    const double value = double(s.*member);
                    if (std::isfinite(value) && value >= min && value <= max) return;
                    const std::string range = max == kUnbounded ? "below " + shortest(min)
                                                                : "outside " + shortest(min) + ".." + shortest(max);
                    throw UsageError(what + " " + shortest(s.*member) + " is " +
                                     (std::isfinite(value) ? range : "not finite") + unit);
                }};
}

// `row`, reading "off" as 0 too.
SettingInfo off_is_zero(SettingInfo row) {
    row.parse = [parse = row.parse](RenderSettings& s, std::string_view text) { parse(s, text == "off" ? "0" : text); };
    return row;
}

std::vector<SettingInfo> make_setting_table() {
    using enum SettingEffect;
    return {
        integer_in("tile", &RenderSettings::tile_size, kMinTileSize, kMaxTileSize, "shadow tile size", frame,
                   "Shadow map tile size (texels per side)"),
        choice("tile-sizes", &RenderSettings::tile_sizing, frame,
               "Shadow tile sizes: share (power-of-two tiles from 128^2 to 1024^2 with areas following each light's "
               "luminance share), sqrt (following its square root), both within the budget of N x tile^2 texels, or "
               "uniform (every tile tile^2); lights sampled every frame keep uniform tiles"),
        integer_of("depth-bits", &RenderSettings::depth_bits, std::array{16, 32}, "shadow depth bits", frame,
                   "Shadow depth bits: 16 or 32 (float)"),
        choice("pcf", &RenderSettings::pcf, programs, "Shadow filter: 2x2 (hardware) or wide (3x3 taps)"),
        number_in("slope-bias", &RenderSettings::slope_bias, 0.0, kUnbounded, "slope bias", "", frame,
                  "Receiver-plane depth bias: the depth change of the receiver's plane over the filter, times this"),
        number_in("normal-offset", &RenderSettings::normal_offset, 0.0, kUnbounded, "normal offset", "", frame,
                  "Receiver moved along its normal by this many shadow texels"),
        number_in("depth-bias", &RenderSettings::depth_bias, 0.0, kUnbounded, "depth bias", "", frame,
                  "Receiver depth lowered by this many shadow texels"),
        choice("specular", &RenderSettings::specular, programs, "blended (Barsi et al.) or single (cos^n psi_c)"),
        choice("cap", &RenderSettings::cap, frame, "Cell cap: solid-angle or weighted (radiance-weighted)"),
        choice("diffuse", &RenderSettings::diffuse, programs,
               "center (the paper's sample) or cap (exact clamped cosine)"),
        choice("shading", &RenderSettings::shading, programs,
               "cells (the paper's sum over the cells) or ratio (unshadowed light from the prefiltered map, "
               "shadowed fraction from the cells)"),
        choice("shadows", &RenderSettings::shadows, programs,
               "Each cell's shadow: hard (one 2x2 lookup at its centre direction) or soft (a penumbra as wide as the "
               "cell's cap, percentage-closer soft shadows)"),
        choice("shadow-rate", &RenderSettings::shadow_rate, programs,
               "Ratio shading only (no effect with --shading cells): the shadowed fraction evaluated in every "
               "shaded fragment (fragment), once per pixel (pixel) or once per 2x2 pixels (half) in a pass of its "
               "own, then looked up with depth-aware weights; adaptive: per 2x2 pixels, and per pixel where "
               "those disagree"),
        on_off("fraction-filter", &RenderSettings::fraction_filter, frame,
               "With --shadow-rate half, pixel or adaptive: the shadowed fraction's texels averaged over the 3x3 about "
               "them on their surface, where they differ little (the soft shadows' noise), before they are looked up"),
        on_off("sun-per-pixel", &RenderSettings::sun_per_pixel, programs,
               "With --shadow-rate half: the sun's shadow (the brightest cell, where it stands out) looked up again "
               "at each pixel, so that its edges lie where a per-pixel fraction puts them"),
        on_off("background", &RenderSettings::background, frame, "Draw the environment behind the objects"),
        on_off("base-color-texture", &RenderSettings::base_color_texture, frame,
               "Base-colour textures multiply the objects' base colour (off: the material's factors alone)"),
        on_off("emission-texture", &RenderSettings::emission_texture, frame,
               "Emission textures multiply the objects' emission (off: the emission factor alone)"),
        on_off("occlusion-texture", &RenderSettings::occlusion_texture, frame,
               "Occlusion textures darken the light the objects reflect (off: none)"),
        on_off("metallic-roughness-texture", &RenderSettings::metallic_roughness_texture, frame,
               "Metallic-roughness textures multiply the objects' metallic and roughness factors, in ratio shading "
               "(off: the factors alone)"),
        on_off("normal-texture", &RenderSettings::normal_texture, frame,
               "Normal maps bend the objects' shading normals (off: the interpolated vertex normals)"),
        integer_of("msaa", &RenderSettings::msaa, kMsaaSampleCounts, "MSAA samples", frame,
                   "Multisample anti-aliasing: samples per pixel, averaged in linear HDR before tone mapping"),
        choice("atlas", &RenderSettings::atlas, programs,
               "How the shadow atlas is drawn: clip-distances (one draw per mesh), viewport-array, per-tile "
               "(baseline)"),
        on_off("skip-lights", &RenderSettings::skip_lights, lights,
               "Skip the lights hidden by the ground or negligible"),
        off_is_zero(number_in("caster-lod", &RenderSettings::caster_lod, 0.0, double(kMaxCasterLod), "caster LOD error",
                              " shadow texels", frame,
                              "Shadow-caster LOD error in shadow texels, or off (the full meshes)")),
        on_off("caster-lod-tiles", &RenderSettings::caster_lod_per_tile, frame,
               "Caster LOD chosen per tile from its own texels (off: from the frame's smallest texels)"),
        on_off("prepass", &RenderSettings::depth_prepass, programs, "Depth pre-pass before shading"),
        on_off("ubo", &RenderSettings::lights_uniform_block, programs,
               "Light records in a uniform block (else a storage block)"),
        on_off("cull", &RenderSettings::cull_back_faces, frame, "Closed casters drawn with back faces culled"),
        on_off("specialise", &RenderSettings::specialise_shaders, frame,
               "Objects without a specular part shaded by a shader without it"),
        on_off("tiles", &RenderSettings::shadow_tile_lists, programs,
               "With the pre-pass: per screen tile, only the lights whose shadow tile sees it"),
        on_off("flat", &RenderSettings::flat_receivers, frame,
               "With the tile lists: diffuse planes take the unshadowed sum from the CPU"),
        on_off("shadow-cache", &RenderSettings::shadow_cache, frame,
               "Keep the depths of the casters that do not move from frame to frame"),
        choice("shadow-fit", &RenderSettings::shadow_fit, frame,
               "Shadow projections fitted to this frame's casters (frame) or to the whole animation's"),
    };
}

}  // namespace

std::string SettingInfo::values() const {
    if (!choices.empty()) {
        std::string text;
        for (const std::string& choice : choices) text += (text.empty() ? "" : "|") + choice;
        return text;
    }
    return max == kUnbounded ? ">= " + shortest(min) : shortest(min) + ".." + shortest(max);
}

std::span<const SettingInfo> setting_table() {
    static const std::vector<SettingInfo> table = make_setting_table();
    return table;
}

const SettingInfo* find_setting(std::string_view name) {
    for (const SettingInfo& setting : setting_table())
        if (setting.name == name) return &setting;
    return nullptr;
}

std::span<const int> msaa_sample_counts() {
    return kMsaaSampleCounts;
}

void validate(const RenderSettings& settings) {
    for (const SettingInfo& setting : setting_table()) setting.check(settings);
}

RenderSettings baseline(RenderSettings settings) {
    settings.caster_lod = 0.0f;
    settings.depth_prepass = false;
    settings.lights_uniform_block = false;
    settings.cull_back_faces = false;
    settings.specialise_shaders = false;
    settings.shadow_tile_lists = false;
    settings.flat_receivers = false;
    settings.shadow_cache = false;
    settings.shadow_fit = ShadowFit::frame;
    return settings;
}

}  // namespace envshadow::render
