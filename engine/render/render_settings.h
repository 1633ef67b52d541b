#pragma once
// What the renderer can be asked to do differently; the viewer and `bench` change these between
// frames, `envshadow render` maps its options onto them.
#include <string_view>

namespace envshadow::render {

// How the tiles of the shadow atlas are kept apart while drawing (glsl/shadow_atlas.vert).
enum class AtlasMode {
    clip_distances,  // one instanced draw per mesh for all tiles; clip distances cut each tile
    viewport_array,  // instanced draws in batches of GL_MAX_VIEWPORTS, instance -> viewport
    per_tile,        // baseline: one draw per mesh and tile, the viewport set to the tile
};
enum class PcfKernel { hardware_2x2, wide };
enum class SpecularMode { blended, single };   // Barsi et al.'s blended average, or k_s cos^n psi_c
enum class CapKind { solid_angle, weighted };  // DESIGN.md §3: cos_radius or cos_radius_weighted
enum class DiffuseMode { center, cap };        // k_d cos theta_c, or its exact average over the cap

struct RenderSettings {
    int tile_size = 256;  // 128..2048
    int depth_bits = 16;  // 16 or 32
    PcfKernel pcf = PcfKernel::hardware_2x2;
    // Bias against shadow acne: the casters' depth is pushed back by glPolygonOffset(slope, 1)
    // (slope-scaled), the receiver is moved along its normal by `normal_offset` shadow texels
    // (scaled by sin theta, at least a fifth) and its depth lowered by `depth_bias` texels.
    float slope_bias = 2.0f;
    float normal_offset = 1.0f;
    float depth_bias = 1.0f;
    SpecularMode specular = SpecularMode::blended;
    CapKind cap = CapKind::weighted;
    DiffuseMode diffuse = DiffuseMode::center;
    bool background = true;
    AtlasMode atlas = AtlasMode::clip_distances;
    bool skip_lights = true;  // drop lights hidden by the ground or negligible (render/lights.h)
    // Optimisations of issue 10 (docs/PERFORMANCE.md); baseline() turns them all off.
    // Shadow casters drawn at the coarsest level of detail whose error is at most this fraction of
    // the smallest atlas texel (render/caster_lod.h); 0: the full meshes.
    float caster_lod = 0.5f;
    // Depth-only pass of the objects first, then the N-light shading once per visible pixel
    // (depth test EQUAL) instead of once per rasterised fragment.
    bool depth_prepass = true;
};

// The first working renderer's settings (issue 10's baseline): `settings` with every optimisation
// of issue 10 off.
RenderSettings baseline(RenderSettings settings);

// `settings` changed by a variant of `bench --variants`: comma-separated items, each a preset
// ("baseline": baseline(); "optimised" or "default": nothing changed) or key=value, with keys
// caster-lod (texels; "off" = 0), prepass (on/off), depth-bits, tile, atlas, pcf. Applied left
// to right; validated. UsageError naming `option` for anything else.
RenderSettings apply_variant(RenderSettings settings, std::string_view variant, std::string_view option);

std::string_view to_string(AtlasMode mode);
std::string_view to_string(PcfKernel kernel);
std::string_view to_string(SpecularMode mode);
std::string_view to_string(CapKind kind);
std::string_view to_string(DiffuseMode mode);
// Parse the names above ("2x2"/"wide", "blended"/"single", "solid-angle"/"weighted",
// "center"/"cap", "clip-distances"/"viewport-array"/"per-tile"); UsageError naming `option`.
AtlasMode parse_atlas_mode(std::string_view name, std::string_view option);
PcfKernel parse_pcf_kernel(std::string_view name, std::string_view option);
SpecularMode parse_specular_mode(std::string_view name, std::string_view option);
CapKind parse_cap_kind(std::string_view name, std::string_view option);
DiffuseMode parse_diffuse_mode(std::string_view name, std::string_view option);

// UsageError if a value is out of range (tile size, depth bits, negative biases, caster LOD).
void validate(const RenderSettings& settings);

}  // namespace envshadow::render
