#pragma once
// What the renderer can be asked to do differently, and the table that names, parses, formats and
// checks each setting (setting_table()): the commands' options, `bench --variants`, the viewer's
// screenshot JSON and validate() all read it.
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/enum_names.h"

namespace envshadow::render {

using envshadow::to_string;  // of the enums below, through their enum_names()

// How the tiles of the shadow atlas are kept apart while drawing (glsl/shadow_atlas.vert).
enum class AtlasMode {
    clip_distances,  // one instanced draw per mesh for all tiles; clip distances cut each tile
    viewport_array,  // instanced draws in batches of GL_MAX_VIEWPORTS, instance -> viewport
    per_tile,        // baseline: one draw per mesh and tile, the viewport set to the tile
};
inline constexpr EnumName<AtlasMode> kAtlasModeNames[] = {{AtlasMode::clip_distances, "clip-distances"},
                                                          {AtlasMode::viewport_array, "viewport-array"},
                                                          {AtlasMode::per_tile, "per-tile"}};
constexpr std::span<const EnumName<AtlasMode>> enum_names(AtlasMode) {
    return kAtlasModeNames;
}

enum class PcfKernel { hardware_2x2, wide };
inline constexpr EnumName<PcfKernel> kPcfKernelNames[] = {{PcfKernel::hardware_2x2, "2x2"}, {PcfKernel::wide, "wide"}};
constexpr std::span<const EnumName<PcfKernel>> enum_names(PcfKernel) {
    return kPcfKernelNames;
}

enum class SpecularMode { blended, single };  // Barsi et al.'s blended average, or k_s cos^n psi_c
inline constexpr EnumName<SpecularMode> kSpecularModeNames[] = {{SpecularMode::blended, "blended"},
                                                                {SpecularMode::single, "single"}};
constexpr std::span<const EnumName<SpecularMode>> enum_names(SpecularMode) {
    return kSpecularModeNames;
}

enum class CapKind { solid_angle, weighted };  // docs/DESIGN.md §3: cos_radius or cos_radius_weighted
inline constexpr EnumName<CapKind> kCapKindNames[] = {{CapKind::solid_angle, "solid-angle"},
                                                      {CapKind::weighted, "weighted"}};
constexpr std::span<const EnumName<CapKind>> enum_names(CapKind) {
    return kCapKindNames;
}

enum class DiffuseMode { center, cap };  // k_d cos theta_c, or its exact average over the cap
inline constexpr EnumName<DiffuseMode> kDiffuseModeNames[] = {{DiffuseMode::center, "center"},
                                                              {DiffuseMode::cap, "cap"}};
constexpr std::span<const EnumName<DiffuseMode>> enum_names(DiffuseMode) {
    return kDiffuseModeNames;
}

// The paper's sum over the cells, or the ratio estimator (docs/DESIGN.md §4.1): the unshadowed reflection
// from the prefiltered map (Renderer::set_prefiltered), the cells' estimate only for the shadowed fraction.
enum class ShadingMode { cells, ratio };
inline constexpr EnumName<ShadingMode> kShadingModeNames[] = {{ShadingMode::cells, "cells"},
                                                              {ShadingMode::ratio, "ratio"}};
constexpr std::span<const EnumName<ShadingMode>> enum_names(ShadingMode) {
    return kShadingModeNames;
}

// Each cell's shadow lookup: the hard 2x2 comparison at the cell's centre direction, or a penumbra as
// wide as the cell's cap sees it (percentage-closer soft shadows per tile, docs/DESIGN.md §5.9).
enum class ShadowMode { hard, soft };
inline constexpr EnumName<ShadowMode> kShadowModeNames[] = {{ShadowMode::hard, "hard"}, {ShadowMode::soft, "soft"}};
constexpr std::span<const EnumName<ShadowMode>> enum_names(ShadowMode) {
    return kShadowModeNames;
}

// Where ratio shading evaluates the cells' shadowed fraction (docs/DESIGN.md §5.14): in every shaded
// fragment with its unshadowed part (fragment), or in a pass of its own at one sample per pixel (pixel) or
// per 2x2 pixels (half), which the shading then looks up beside its surface with depth-aware weights, so
// that the N-cell loop no longer runs per MSAA sample; adaptive: per 2x2 pixels, then once per pixel where
// the 2x2 samples about it disagree (a shadow's edge narrower than two pixels). The paper's sum
// (ShadingMode::cells) does not split.
enum class ShadowRate { fragment, pixel, half, adaptive };
inline constexpr EnumName<ShadowRate> kShadowRateNames[] = {{ShadowRate::fragment, "fragment"},
                                                            {ShadowRate::pixel, "pixel"},
                                                            {ShadowRate::half, "half"},
                                                            {ShadowRate::adaptive, "adaptive"}};
constexpr std::span<const EnumName<ShadowRate>> enum_names(ShadowRate) {
    return kShadowRateNames;
}

// How each light's orthographic projection is fitted to the shadow casters (docs/DESIGN.md §5.11): to
// this frame's boxes (the sharpest fit, changed whenever anything moves), or to their boxes over the
// whole animation (the same every frame, so the shadow cache keeps the casters that do not move while
// others move; coarser texels: 0.37 of the density on flyover, docs/PERFORMANCE.md).
enum class ShadowFit { frame, animation };
inline constexpr EnumName<ShadowFit> kShadowFitNames[] = {{ShadowFit::frame, "frame"},
                                                          {ShadowFit::animation, "animation"}};
constexpr std::span<const EnumName<ShadowFit>> enum_names(ShadowFit) {
    return kShadowFitNames;
}

// How big each light's shadow tile is (render/shadow_atlas_layout.h): all tile_size^2, or power-of-two
// sizes whose areas follow the light's luminance share (share) or its square root (sqrt), within the
// same budget of N tile_size^2 texels.
enum class TileSizing { uniform, share, sqrt_share };
inline constexpr EnumName<TileSizing> kTileSizingNames[] = {
    {TileSizing::uniform, "uniform"}, {TileSizing::share, "share"}, {TileSizing::sqrt_share, "sqrt"}};
constexpr std::span<const EnumName<TileSizing>> enum_names(TileSizing) {
    return kTileSizingNames;
}

inline constexpr float kMaxCasterLod = 4.0f;  // shadow texels

struct RenderSettings {
    int tile_size = 256;  // kMinTileSize..kMaxTileSize (render/shadow_atlas_layout.h)
    // Lights handed over every frame (the GPU sampler) keep uniform tiles whatever this says. share:
    // lower error than uniform and sqrt at the same budget on engine/courtyard, figure/city and
    // figure/studio (docs/ACCURACY.md).
    TileSizing tile_sizing = TileSizing::share;
    int depth_bits = 16;  // 16 or 32
    PcfKernel pcf = PcfKernel::hardware_2x2;
    // Bias against shadow acne (docs/DESIGN.md §5.3), all at the receiver: each texel the filter reads
    // is compared with the receiver's plane carried to that texel, so its own plane needs no bias; its
    // depth is lowered by `depth_bias` texels and by `slope_bias` texels of its plane's depth slope
    // (0: more lets light through a concave corner, a wall under a roof, docs/accuracy/interiors_by_hand.md);
    // it may be moved along its normal by `normal_offset` texels too (scaled by sin theta, at least a
    // fifth). The casters are drawn with glPolygonOffset(0, 1): one step of the map's depth precision;
    // a larger caster offset leaks light into slots a few texels wide (docs/accuracy/engine_by_hand.md).
    float slope_bias = 0.0f;
    float normal_offset = 0.0f;
    float depth_bias = 0.5f;
    SpecularMode specular = SpecularMode::blended;
    CapKind cap = CapKind::weighted;
    DiffuseMode diffuse = DiffuseMode::center;
    ShadingMode shading = ShadingMode::cells;
    ShadowMode shadows = ShadowMode::hard;
    ShadowRate shadow_rate = ShadowRate::fragment;  // ShadingMode::ratio only
    // ShadowRate::half, pixel and adaptive: the fraction's texels filtered over their surface
    // (glsl/fraction_filter.frag), which averages the soft shadows' per-texel disc rotations.
    bool fraction_filter = true;
    // ShadowRate::half: the sun's shadow (render::sun_light) looked up again at each pixel
    // (glsl/shade_sun_per_pixel.glsl), so that its edges are placed per pixel, not per 2x2.
    bool sun_per_pixel = true;
    bool background = true;
    // Objects' base-colour textures (glTF's baseColorTexture) multiply their base colour; off: the
    // material's factors alone, as glTF viewers' debug views switch textures off one at a time.
    bool base_color_texture = true;
    bool emission_texture = true;            // off: the emission factor alone
    bool occlusion_texture = true;           // off: no occlusion from textures (glTF's occlusionTexture)
    bool metallic_roughness_texture = true;  // off: the metallic and roughness factors alone
    bool normal_texture = true;              // off: the interpolated vertex normals (glTF's normalTexture)
    // Samples per pixel of the shading target (multisample anti-aliasing; one of msaa_sample_counts()),
    // resolved to one linear HDR colour per pixel (their mean) before tone mapping. The driver's maximum
    // caps it (Renderer::samples()). 1 here: the per-pixel values the engine's tests compare; the commands
    // start from 4 (app/setting_options.h, command_defaults()).
    int msaa = 1;
    AtlasMode atlas = AtlasMode::clip_distances;
    bool skip_lights = true;  // drop lights hidden by the ground or negligible (render/lights.h)
    // The optimisations below are on by default; baseline() turns them off (docs/PERFORMANCE.md).
    // Shadow casters drawn at the coarsest level of detail whose measured error is at most this many
    // of the frame's smallest atlas texels (render/caster_lod.h); 0: the full meshes. A surface moved
    // by d texels along its normal moves d / cos theta <= d (1 + tan theta) along the light: depth_bias
    // covers the d (0.5 texel), slope_bias (default 0) the d tan theta, which at grazing light may shadow
    // a receiver by its own simplified surface (not seen on engine or viruses at 0.3, docs/DESIGN.md
    // §5.3); thin parts a few texels across (the viruses' spikes at 128^2 tiles) change their shadows'
    // speckle visibly from 0.4 texel on (the viruses' golden image), so 0.3; flyover's figures take 1
    // texel invisibly (docs/PERFORMANCE.md).
    float caster_lod = 0.3f;  // 0..kMaxCasterLod
    // The caster LOD's texel is each tile's own (a 128^2 tile's texels are 8 times a 1024^2 tile's over
    // the same casters, so it takes a coarser level), not the frame's smallest: the same bound, per tile.
    bool caster_lod_per_tile = true;
    // Depth-only pass of the objects first, then the N-light shading once per visible pixel
    // (depth test EQUAL) instead of once per rasterised fragment.
    bool depth_prepass = true;
    // Light records in a uniform block (needs GL_MAX_UNIFORM_BLOCK_SIZE >= 256 records, else the
    // storage block is used) instead of a shader storage block.
    bool lights_uniform_block = true;
    // Closed casters (every edge shared by two oppositely wound triangles) drawn into the atlas with
    // back faces culled: the nearest surface seen from a light is always a front face of a closed
    // mesh, so the depth maps are the same with half the triangles. Open meshes keep both faces.
    bool cull_back_faces = true;
    // Objects whose material has no specular part shaded by a shader compiled without it.
    bool specialise_shaders = true;
    // With the depth pre-pass: per 16x16 screen tile, the lights whose shadow tile can see any visible
    // receiver there (glsl/shadow_tiles.comp); the others' visibility is exactly 1 and not looked up.
    bool shadow_tile_lists = true;
    // With the tile lists: planes with a diffuse material (the ground) take the unshadowed sum of the
    // lights, the same for all their pixels, from the CPU instead of summing it per pixel.
    bool flat_receivers = true;
    // The depths of the casters that do not move (Object::moves()) kept in a layer of their
    // own, redrawn only when the lights, the scene, the fits or the atlas settings change; each frame
    // copies it into the atlas and draws only the moving casters over it, and a frame where nothing
    // moves draws no atlas pass at all (docs/DESIGN.md §5.11). The same atlas as drawing every caster
    // (the depth test keeps the nearest whatever the order). With per-frame fits a frame where anything
    // moves draws every caster (its tiles moved); ShadowFit::animation keeps them put, but changes the
    // animated scenes' shadows (viruses' golden: 2.5% of pixels), so it is asked for, not the default.
    bool shadow_cache = true;
    ShadowFit shadow_fit = ShadowFit::frame;
};

// The first working renderer's settings: `settings` with every optimisation off (caster LOD, pre-pass,
// uniform block, back-face culling, specialised shaders, tile lists, flat receivers), and the shadow
// cache off with per-frame fits.
RenderSettings baseline(RenderSettings settings);

// What a change of a setting makes Renderer::set_settings redo.
enum class SettingEffect {
    frame,     // nothing: render() reads it as it draws (what it sizes, it reallocates on demand)
    lights,    // the lights are selected again
    programs,  // it is part of the shader variant key (render/shader_variant.h)
};

// How a setting's value is written.
enum class SettingKind {
    choice,   // a name of an enum (core/enum_names.h)
    on_off,   // "on" or "off"
    integer,  // one of `choices`, or within min..max
    number,   // finite, within min..max
};

// One row of the table of RenderSettings: one name per setting, as the command line (--name value),
// `bench --variants` (name=value) and the viewer's screenshot JSON spell it; how to read, write and
// check its value; what a change costs the renderer.
struct SettingInfo {
    std::string_view name;  // "tile-sizes"
    std::string_view help;  // one sentence for --help, without the default
    SettingKind kind = SettingKind::choice;
    SettingEffect effect = SettingEffect::frame;
    std::vector<std::string> choices;  // choice, on_off and integer sets: every value; empty: min..max
    double min = 0.0, max = 0.0;       // integer and number without choices (max may be infinity)
    // `text` into its member of `settings`; UsageError "'x' is not one of a, b" for text that is no value.
    std::function<void(RenderSettings& settings, std::string_view text)> parse;
    // Its member as text that parse() reads back to the same value.
    std::function<std::string(const RenderSettings& settings)> format;
    // UsageError in the engine's words if its member is out of range ("shadow tile size 64 is outside
    // 128..2048").
    std::function<void(const RenderSettings& settings)> check;

    // "2x2|wide", "on|off", "128..2048": the values, for help texts and messages.
    std::string values() const;
};

// Every member of RenderSettings, in the order --help lists them.
std::span<const SettingInfo> setting_table();
// The row named `name`, or nullptr.
const SettingInfo* find_setting(std::string_view name);

// Samples per pixel of the shading target that RenderSettings::msaa may ask for: 1, 2, 4, 8.
std::span<const int> msaa_sample_counts();

// UsageError if a value is out of range (every row's check()).
void validate(const RenderSettings& settings);

}  // namespace envshadow::render
