#pragma once
// What the renderer can be asked to do differently; the viewer and `bench` change these between
// frames, `envshadow render` maps its options onto them.
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace envshadow::render {

// How the tiles of the shadow atlas are kept apart while drawing (glsl/shadow_atlas.vert).
enum class AtlasMode {
    clip_distances,  // one instanced draw per mesh for all tiles; clip distances cut each tile
    viewport_array,  // instanced draws in batches of GL_MAX_VIEWPORTS, instance -> viewport
    per_tile,        // baseline: one draw per mesh and tile, the viewport set to the tile
};
enum class PcfKernel { hardware_2x2, wide };
enum class SpecularMode { blended, single };   // Barsi et al.'s blended average, or k_s cos^n psi_c
enum class CapKind { solid_angle, weighted };  // docs/DESIGN.md §3: cos_radius or cos_radius_weighted
enum class DiffuseMode { center, cap };        // k_d cos theta_c, or its exact average over the cap
// The paper's sum over the cells, or the ratio estimator (docs/DESIGN.md §4.1): the unshadowed reflection
// from the prefiltered map (Renderer::set_prefiltered), the cells' estimate only for the shadowed fraction.
enum class ShadingMode { cells, ratio };
// Each cell's shadow lookup: the hard 2x2 comparison at the cell's centre direction, or a penumbra as
// wide as the cell's cap sees it (percentage-closer soft shadows per tile, docs/DESIGN.md §5.9).
enum class ShadowMode { hard, soft };

// How each light's orthographic projection is fitted to the shadow casters (docs/DESIGN.md §5.11): to
// this frame's boxes (the sharpest fit, changed whenever anything moves), or to their boxes over the
// whole animation (the same every frame, so the shadow cache keeps the casters that do not move while
// others move; coarser texels: 0.37 of the density on flyover, docs/PERFORMANCE.md).
enum class ShadowFit { frame, animation };

// How big each light's shadow tile is (render/shadow_atlas_layout.h): all tile_size^2, or power-of-two
// sizes whose areas follow the light's luminance share (share) or its square root (sqrt), within the
// same budget of N tile_size^2 texels.
enum class TileSizing { uniform, share, sqrt_share };

inline constexpr float kMaxCasterLod = 4.0f;  // shadow texels

// Samples per pixel of the shading target that RenderSettings::msaa may ask for: 1, 2, 4, 8.
std::span<const int> msaa_sample_counts();

struct RenderSettings {
    int tile_size = 256;  // kMinTileSize..kMaxTileSize (render/shadow_atlas_layout.h)
    // Lights handed over every frame (the GPU sampler) keep uniform tiles whatever this says. share:
    // lower error than uniform and sqrt at the same budget on engine/courtyard, figure/city and
    // figure/studio (docs/ACCURACY.md, issue 14 part 3).
    TileSizing tile_sizing = TileSizing::share;
    int depth_bits = 16;  // 16 or 32
    PcfKernel pcf = PcfKernel::hardware_2x2;
    // Bias against shadow acne (docs/DESIGN.md §5.3), all at the receiver: each texel the filter reads
    // is compared with the receiver's plane carried to that texel, so its own plane needs no bias; its
    // depth is lowered by `depth_bias` texels and by `slope_bias` texels of its plane's depth slope
    // (0: more lets light through a concave corner, a wall under a roof, docs/accuracy/interiors_by_hand.md);
    // it may be moved along its normal by `normal_offset` texels too (scaled by sin theta, at least a
    // fifth). The casters are drawn with glPolygonOffset(0, 1): one step of the map's depth precision.
    // Before issue 14's engine study the casters took glPolygonOffset(2, 1) and the receivers 1 texel
    // of each of the other two: light leaked into slots a few texels wide (engine/courtyard 5.1% against
    // 2.1%; docs/accuracy/engine_by_hand.md).
    float slope_bias = 0.0f;
    float normal_offset = 0.0f;
    float depth_bias = 0.5f;
    SpecularMode specular = SpecularMode::blended;
    CapKind cap = CapKind::weighted;
    DiffuseMode diffuse = DiffuseMode::center;
    ShadingMode shading = ShadingMode::cells;
    ShadowMode shadows = ShadowMode::hard;
    bool background = true;
    // Samples per pixel of the shading target (multisample anti-aliasing; one of msaa_sample_counts()),
    // resolved to one linear HDR colour per pixel (their mean) before tone mapping. The driver's maximum
    // caps it (Renderer::samples()). 1 here: the per-pixel values the engine's tests compare; the commands
    // default to 4 (app/options.h).
    int msaa = 1;
    AtlasMode atlas = AtlasMode::clip_distances;
    bool skip_lights = true;  // drop lights hidden by the ground or negligible (render/lights.h)
    // Optimisations of issue 10 (docs/PERFORMANCE.md); baseline() turns them all off.
    // Shadow casters drawn at the coarsest level of detail whose measured error is at most this many
    // of the frame's smallest atlas texels (render/caster_lod.h); 0: the full meshes. A surface moved
    // by d texels along its normal moves d / cos theta <= d (1 + tan theta) along the light: depth_bias
    // covers the d (0.5 texel), slope_bias (default 0) the d tan theta, which at grazing light may shadow
    // a receiver by its own simplified surface (not seen on engine or viruses at 0.3, docs/DESIGN.md
    // §5.3); thin parts a few texels across (the viruses'
    // spikes at 128^2 tiles) change their shadows' speckle visibly already at 0.4 texel (golden fails:
    // 0.22% of pixels differ, 0.2% allowed), so 0.3; flyover's figures take 1 texel invisibly
    // (docs/PERFORMANCE.md).
    float caster_lod = 0.3f;  // 0..kMaxCasterLod
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
    // Issue 18: the depths of the casters that do not move (Object::moves()) kept in a layer of their
    // own, redrawn only when the lights, the scene, the fits or the atlas settings change; each frame
    // copies it into the atlas and draws only the moving casters over it, and a frame where nothing
    // moves draws no atlas pass at all (docs/DESIGN.md §5.11). The same atlas as drawing every caster
    // (the depth test keeps the nearest whatever the order). With per-frame fits a frame where anything
    // moves draws every caster (its tiles moved); ShadowFit::animation keeps them put, but changes the
    // animated scenes' shadows (viruses' golden: 2.5% of pixels), so it is asked for, not the default.
    bool shadow_cache = true;
    ShadowFit shadow_fit = ShadowFit::frame;
};

// The on/off optimisations of issue 10, each by its short name (docs/PERFORMANCE.md's tables, bench's
// variants); caster_lod, the eighth, is a number.
struct OptimisationSwitch {
    std::string_view name;
    bool RenderSettings::*member;
};
std::span<const OptimisationSwitch> optimisation_switches();

// The first working renderer's settings (issue 10's baseline): `settings` with every optimisation
// of issue 10 off, and issue 18's shadow cache off with per-frame fits.
RenderSettings baseline(RenderSettings settings);

std::string_view to_string(AtlasMode mode);
std::string_view to_string(PcfKernel kernel);
std::string_view to_string(SpecularMode mode);
std::string_view to_string(CapKind kind);
std::string_view to_string(DiffuseMode mode);
std::string_view to_string(ShadingMode mode);
std::string_view to_string(TileSizing sizing);
std::string_view to_string(ShadowMode mode);
std::string_view to_string(ShadowFit fit);
// Parse the names above ("2x2"/"wide", "blended"/"single", "solid-angle"/"weighted",
// "center"/"cap", "cells"/"ratio", "clip-distances"/"viewport-array"/"per-tile",
// "uniform"/"share"/"sqrt", "hard"/"soft", "frame"/"animation"); UsageError listing the names.
AtlasMode parse_atlas_mode(std::string_view name);
PcfKernel parse_pcf_kernel(std::string_view name);
SpecularMode parse_specular_mode(std::string_view name);
CapKind parse_cap_kind(std::string_view name);
DiffuseMode parse_diffuse_mode(std::string_view name);
ShadingMode parse_shading_mode(std::string_view name);
TileSizing parse_tile_sizing(std::string_view name);
ShadowMode parse_shadow_mode(std::string_view name);
ShadowFit parse_shadow_fit(std::string_view name);

// The names a setting accepts, in the order above: for the command line's validators, so that a
// name added to a table is accepted everywhere at once.
template <typename Enum>
std::vector<std::string> names();
template <>
std::vector<std::string> names<AtlasMode>();
template <>
std::vector<std::string> names<PcfKernel>();
template <>
std::vector<std::string> names<SpecularMode>();
template <>
std::vector<std::string> names<CapKind>();
template <>
std::vector<std::string> names<DiffuseMode>();
template <>
std::vector<std::string> names<ShadingMode>();
template <>
std::vector<std::string> names<TileSizing>();
template <>
std::vector<std::string> names<ShadowMode>();
template <>
std::vector<std::string> names<ShadowFit>();

// UsageError if a value is out of range (tile size, depth bits, MSAA samples, negative biases, caster LOD).
void validate(const RenderSettings& settings);

}  // namespace envshadow::render
