#pragma once
// The per-frame renderer (Barsi et al., "Image-Based Illumination on the GPU"): every frame the
// shadow casters are drawn into one depth tile per cell of the environment (the shadow atlas), then
// the objects are shaded by summing V * L~_i * a over the cells, and the environment fills the
// background. What to draw is planned on the CPU (render/frame_plan.h); the renderer uploads the
// plan and draws it. The viewer, `bench` and `envshadow render` drive it the same way:
//
//   Renderer renderer(settings);        // a GL 4.5 core context must be current
//   renderer.set_scene(scene);          // meshes to the GPU, materials, animation, env rotation
//   renderer.set_environment(map);      // the background
//   renderer.set_lights(cells);         // map-space cells of the decomposition
//   FrameStats stats = renderer.render(time, camera_view(scene, width, height, time));
//   Image linear = renderer.read_back();
//
// render() and set_lights() create no GL objects and reuse their buffers from frame to frame; only a
// change of image size, light count or settings reallocates (and the shadow cache's layer is made the
// first time something moves; the returned pass-time list is the one per-frame vector).
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <tuple>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/image.h"
#include "env/cells.h"
#include "env/compact_sources.h"
#include "env/environment.h"
#include "env/ggx_prefilter.h"
#include "env/prefilter.h"
#include "gl/objects.h"
#include "gl/shader.h"
#include "gl/timer.h"
#include "render/frame_plan.h"
#include "render/gpu_mesh.h"
#include "render/lights.h"
#include "render/render_settings.h"
#include "render/shader_variant.h"
#include "render/shadow_atlas_layout.h"
#include "scene/scene.h"

namespace envshadow::render {

struct FrameStats {
    std::vector<gl::PassTime> passes;  // "shadow atlas", "shading", "background" (GPU milliseconds)
    int lights = 0;                    // lights summed by the shader (= atlas tiles)
    int lights_below_ground = 0;       // skipped (render/lights.h)
    int lights_negligible = 0;
    std::size_t atlas_bytes = 0;
    AtlasLayout atlas;
    std::size_t atlas_triangles = 0;  // caster triangles drawn into the atlas, all tiles together
    // The shadow cache (RenderSettings::shadow_cache, docs/DESIGN.md §5.11) this frame: 1 when the atlas
    // was drawn at all (0: it kept the last frame's depths, nothing having changed), 1 when the layer of
    // the casters that do not move was redrawn, and the moving casters drawn over its copy.
    int atlas_passes = 0;
    int static_layer_renders = 0;
    int moving_casters_drawn = 0;
};

class Renderer {
public:
    explicit Renderer(const RenderSettings& settings = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Redoes only what the change needs (render::SettingEffect): programs of a shader variant not drawn
    // with before are built, those of one seen before reused. Throws UsageError for bad values.
    void set_settings(const RenderSettings& settings);
    const RenderSettings& settings() const { return settings_; }
    // The variant the settings draw with (render/shader_variant.h); the programs built so far: two for
    // every variant (pre-pass, background), kProgramsPerVariant per variant drawn with,
    // shadow_tiles.comp once per sample count the tile lists were drawn at, and the shading from the
    // shadowed-fraction texture once, when first drawn with (RenderSettings::shadow_rate).
    const ShaderVariant& shader_variant() const { return variant_; }
    std::size_t programs_built() const { return library_.programs_built(); }
    // atlas; shading: full, diffuse-only, flat receiver (and glTF's, built once drawn with)
    static constexpr std::size_t kProgramsPerVariant = 4;

    // Uploads the meshes (each shared mesh once) and keeps the objects (materials, transforms,
    // animation) and the environment's rotation. The scene may be destroyed afterwards.
    // `progress` (optional) hears the triangles prepared so far of all there are: seconds per million.
    void set_scene(const Scene& scene, const std::function<void(std::size_t done, std::size_t total)>& progress = {});
    // Changes the material of scene.objects[object] (as given to set_scene) without re-uploading; one that cuts
    // the caster out otherwise renews the shadow cache (docs/DESIGN.md §5.11).
    void set_material(std::size_t object, const Material& material);
    // The lat-long map drawn behind the objects.
    void set_environment(const EnvironmentMap& map);
    // The map prefiltered for ShadingMode::ratio (env/prefilter.h, with the decomposition's hemisphere):
    // uploaded, one texture per level. Ratio shading without it (a viewer whose first map is still loading)
    // leaves the objects black.
    void set_prefiltered(const PrefilteredEnvironment& prefiltered);
    // The map prefiltered for glTF's BRDF (env/ggx_prefilter.h, the same hemisphere) without its compact sources,
    // uploaded with that map (the split sum's mirror, below the sharpest level), the sources and the split sum's
    // DFG table (env/dfg_table.h): ratio shading draws materials with metallic-roughness parameters by them.
    // `prefiltered` must be of `split.rest`. Without it such materials get their Phong stand-in.
    void set_ggx_prefiltered(const GgxPrefilteredEnvironment& prefiltered, const CompactSourceSplit& split);
    // Rotation of the map about +Y (env/orientation.h); set_scene sets the scene's.
    void set_environment_rotation(float degrees);
    // Cells of a decomposition, at most kMaxLights (std::invalid_argument otherwise); map-space ones
    // are rotated into the world by the environment's rotation, world-space ones are taken as they are.
    // Lights handed over anew every frame (the GPU sampler) keep uniform shadow tiles whatever
    // settings().tile_sizing says.
    enum class CellSpace { map, world };
    enum class LightLifetime { fixed, every_frame };
    void set_lights(std::vector<Cell> cells, CellSpace space = CellSpace::map,
                    LightLifetime lifetime = LightLifetime::fixed);

    // How render() times its passes (gl/timer.h): GL_TIME_ELAPSED queries by default.
    void set_pass_timing(gl::PassTiming timing) { timer_.set_mode(timing); }
    gl::PassTiming pass_timing() const { return timer_.mode(); }

    // Renders one frame at animation time `time` into the linear HDR target (RGBA32F): objects
    // alpha 1, background alpha 0 (or transparent black without a background).
    FrameStats render(double time, const CameraView& view);
    // The last frame, linear, row 0 at the top.
    Image read_back() const;

    // The last frame's linear colour, one sample per pixel (the multisampled target resolved).
    const gl::Texture& color_texture() const { return color_; }
    const gl::Texture& environment_texture() const { return environment_; }  // RGB32F lat-long, or empty
    const gl::Texture& atlas_texture() const { return atlas_depth_; }
    // Holds color_texture(): the target itself at one sample per pixel, else the resolve's destination.
    const gl::Framebuffer& framebuffer() const { return samples_ > 1 ? resolved_ : target_; }
    // Samples per pixel drawn: RenderSettings::msaa, capped by the driver's maximum.
    int samples() const { return samples_; }
    // Where in the pixel those samples lie ([0, 1]^2 from the lower left; GL's are implementation-defined):
    // what subpixel_jitter() spreads.
    std::vector<glm::vec2> sample_positions() const;
    const AtlasLayout& atlas_layout() const { return layout_; }
    std::size_t atlas_bytes() const { return layout_.bytes(settings_.depth_bits); }
    int light_count() const { return int(lights_.kept.size()); }

private:
    void select_programs();  // programs_now_ for settings_, its programs built on first use
    void select_lights();
    void ensure_atlas();
    void ensure_target(int width, int height);
    // A shadowed-fraction pass's output (docs/DESIGN.md §5.14): the fraction (RGB) and 1/w (A, 0: no object),
    // the shading normal (RGB), the sun's share and visibility (SUN_PER_PIXEL), and the depth it was drawn with.
    struct FractionTarget {
        gl::Texture fraction, normal, sun, depth;
        gl::Framebuffer framebuffer;
        // `sun`: with the sun's attachment (the fraction pass's with SUN_PER_PIXEL; the refinement has none).
        static FractionTarget create(int width, int height, bool sun, const char* what);
        bool fits(int width, int height, bool with_sun) const {
            return fraction && fraction.width() == width && fraction.height() == height && bool(sun) == with_sun;
        }
    };
    // A fraction and the normals of its texels, as the shading and the refinement read them; with
    // SUN_PER_PIXEL, the sun's share and visibility.
    struct FractionInput {
        const gl::Texture& fraction;
        const gl::Texture& normal;
        const gl::Texture* sun = nullptr;
    };
    // The shadowed-fraction passes' targets for an image of width x height (RenderSettings::shadow_rate).
    void ensure_fraction_target(int width, int height);
    // `input`'s textures bound for `programs` (SHADOWED_FRACTION_IN) drawing an image of `view`'s size.
    static void bind_fraction_input(FractionInput input, std::initializer_list<const gl::Program*> programs,
                                    const CameraView& view);
    static void unbind_fraction_input();
    int drawn_samples() const;  // settings_.msaa capped by max_samples_ (a warning, once, where it is)
    const gl::Program& tiles_program(int samples);  // shadow_tiles.comp for a depth of `samples`, built on first use
    // shade.frag SHADOWED_FRACTION_IN (with METALLIC_ROUGHNESS for glTF's BRDF), built on first use.
    const gl::Program& fraction_shading_program(bool metallic_roughness);
    void upload(const FramePlan& plan);
    void draw_atlas(const FramePlan& plan, FrameStats& stats);
    // Draws the casters `which` accepts (by ObjectFrame index) into every tile, over what the atlas holds or
    // after clearing it.
    enum class AtlasStart { cleared, as_it_is };
    // opaque: the depths (atlas_); translucent: the blended casters' layer (atlas_translucent_, docs/DESIGN.md
    // §5.15), always cleared first.
    enum class CasterLayer { opaque, translucent };
    void draw_casters(const FramePlan& plan, const std::function<bool(std::size_t)>& which, AtlasStart start,
                      CasterLayer layer = CasterLayer::opaque);
    // The opaque casters into atlas_, through the shadow cache (docs/DESIGN.md §5.11).
    void draw_opaque_atlas(const FramePlan& plan, FrameStats& stats);
    void ensure_translucent_layer();
    void draw_objects(const FramePlan& plan, const CameraView& view);
    // The objects' depths into the bound framebuffer, timed as `pass`.
    // Into the bound framebuffer of `samples` samples per pixel.
    void draw_depth_prepass(const FramePlan& plan, const CameraView& view, int samples, const char* pass);
    // Screen-tile light lists from `depth` (of `samples` per pixel) into `lists`, tiles.x by tiles.y.
    void build_tile_lists(const FramePlan& plan, const CameraView& view, const gl::Texture& depth, int samples,
                          const gl::Buffer& lists, glm::ivec2 tiles, const char* pass);
    // The objects shaded into the bound framebuffer, each with the program of its ShadeProgram; tiles_x: the
    // screen tiles per row of the bound tile lists.
    struct ShadePrograms {
        const gl::Program* full;
        const gl::Program* diffuse_only;
        const gl::Program* flat_receiver;
        const gl::Program* metallic_roughness;
    };
    // `objects`: which, in that order; `blending`: the blended objects (draw_blended) over the opaque depths.
    void shade_objects(const FramePlan& plan, const CameraView& view, const ShadePrograms& programs, int tiles_x,
                       std::span<const std::size_t> objects, bool blending = false);
    bool draws_metallic_roughness(const FramePlan& plan) const;
    const gl::Program& metallic_roughness_program(const FramePlan& plan);
    // glTF's BRDF: the compact sources, whose reflection takes the lobe's true shape, in world space.
    void set_compact_sources(GLuint program) const;
    // Ratio shading: the unshadowed part's uniforms, levels and textures of object i (glsl/shade_ratio.glsl).
    // `gltf`: drawn with the METALLIC_ROUGHNESS program.
    void bind_unshadowed_levels(GLuint program, const ObjectFrame& object, std::size_t i, bool gltf) const;
    // The alpha mask's uniforms and the base-colour texture of object i (its cutoff 0 where it has no mask).
    void bind_alpha_mask(GLuint program, const ObjectFrame& object, std::size_t i) const;
    // The front face's winding and whether back faces are culled, for object i drawn for the camera.
    void set_sides(const ObjectFrame& object, std::size_t i) const;
    // The ratio's shadowed fraction into fraction_ (its own pre-pass and tile lists); leaves target_ bound.
    void draw_shadowed_fraction(const FramePlan& plan, const CameraView& view);
    // ShadowRate::adaptive: fraction_ (filtered with fraction_filter) per pixel into refined_, computed again
    // where it varies (its own pre-pass, and the image's tile lists from that); leaves target_ bound.
    void draw_refined_fraction(const FramePlan& plan, const CameraView& view);
    // fraction_ filtered over its surfaces into fraction_filtered_ (glsl/fraction_filter.frag).
    void filter_fraction(const CameraView& view);
    // What the shading takes the fraction from: refined_, or fraction_ filtered.
    FractionInput shading_fraction() const;
    void draw_background(const CameraView& view);
    void draw_blended(const FramePlan& plan, const CameraView& view);

    RenderSettings settings_;
    gl::ShaderLibrary library_;
    // The programs of one shader variant: the atlas's, and shade.frag's full, diffuse-only and flat-receiver ones.
    struct VariantPrograms {
        gl::Program atlas, shade, shade_diffuse, shade_flat;
        gl::Program shade_gltf;    // METALLIC_ROUGHNESS (ratio, or its fraction pass), built once drawn with
        gl::Program atlas_masked;  // ALPHA_MASK with shadow_atlas_mask.frag, built once drawn with
        // ALPHA_BLEND, per fragment (the variant without tile lists and fraction pass), built once drawn with.
        gl::Program blend, blend_diffuse, blend_gltf;
        gl::Program atlas_translucent;  // ALPHA_MASK with shadow_atlas_translucent.frag, built once drawn with
        // SHADOWED_FRACTION_REFINE (ShadowRate::adaptive) with shade, shade_diffuse, shade_flat and shade_gltf's
        // defines, built once drawn with.
        gl::Program refine, refine_diffuse, refine_flat, refine_gltf;
        // SUN_PER_PIXEL: the shading (SHADOWED_FRACTION_IN) with the variant's visibility, built once drawn with.
        gl::Program shade_sun, shade_sun_gltf;
    };
    ShaderSupport support_;
    ShaderVariant variant_;
    std::map<ShaderVariant, VariantPrograms> programs_;  // every variant drawn with so far
    VariantPrograms* programs_now_ = nullptr;            // programs_[variant_]
    gl::Program prepass_program_, background_program_;   // the same for every variant
    gl::Program masked_prepass_program_;                 // ALPHA_MASK; empty until drawn with
    // SHADOWED_FRACTION_IN per (METALLIC_ROUGHNESS, ALPHA_TEST): fraction_shading_program()
    // By METALLIC_ROUGHNESS, ALPHA_TEST, LIGHTS_UNIFORM_BLOCK (fraction_shading_program).
    std::map<std::tuple<bool, bool, bool>, gl::Program> fraction_shading_programs_;
    // shadow_tiles.comp per (lights in a uniform block, sample count): tiles_program()
    std::map<std::pair<bool, int>, gl::Program> tiles_programs_;
    gl::VertexArray empty_vertex_array_;  // the background's vertices come from gl_VertexID
    gl::Sampler atlas_depth_sampler_;     // the atlas's depths, NEAREST, no comparison: the shading's lookups
    gl::GpuTimer timer_;
    bool timer_warmed_up_ = false;

    // This frame's objects by ObjectFrame::blended; draw_blended sorts the blended ones farthest first.
    std::vector<std::size_t> opaque_objects_, blended_objects_;
    std::vector<std::unique_ptr<GpuMesh>> meshes_;
    std::vector<const GpuMesh*> instance_meshes_;  // per object of planner_.objects()
    std::vector<int> instance_of_object_;          // index into instance_meshes_ per scene object; -1: no triangles
    // Base-colour, emission, occlusion and metallic-roughness textures, per object of planner_.objects()
    // (white_texture_ without one); fixed by set_scene (set_material changes the factors only).
    std::vector<std::unique_ptr<gl::Texture>> textures_;
    std::vector<const gl::Texture*> instance_textures_;
    std::vector<const gl::Texture*> instance_emission_textures_;
    std::vector<const gl::Texture*> instance_occlusion_textures_;
    std::vector<const gl::Texture*> instance_metallic_roughness_textures_;
    std::vector<const gl::Texture*> instance_normal_textures_;
    // Per object of planner_.objects(): closed and single-sided (Material::double_sided false), so drawn
    // for the camera with back faces culled; fixed by set_scene.
    std::vector<bool> instance_front_only_;
    gl::Texture white_texture_;
    // Objects whose vertices move (glTF skins and morphs): posed into their own GpuMesh every frame.
    struct DeformingInstance {
        std::size_t instance = 0;  // into instance_meshes_ and the planner's objects
        GpuMesh* mesh = nullptr;
        Object object;
    };
    std::vector<DeformingInstance> deforming_;
    bool has_ground_ = false;
    float rotation_degrees_ = 0.0f;

    std::vector<Cell> cells_;
    CellSpace cell_space_ = CellSpace::map;
    LightSelection lights_;
    FramePlanner planner_;
    std::size_t atlas_triangles_ = 0;
    gl::Buffer light_buffer_;  // room for shader::size::max_lights records, made once

    AtlasLayout layout_;
    bool layout_stale_ = true;  // the lights changed since layout_ was planned
    LightLifetime light_lifetime_ = LightLifetime::fixed;
    std::vector<double> luminance_;  // of the kept lights, for plan_atlas
    int atlas_depth_bits_ = 0;
    gl::Texture atlas_depth_;
    gl::Framebuffer atlas_;
    // The translucent layer (while the scene has blended casters): transmittance (R8), nearest depth (R16), and
    // a framebuffer of the two over atlas_depth_.
    bool translucent_casters_ = false;
    gl::Texture atlas_transmittance_, atlas_translucent_depth_;
    gl::Framebuffer atlas_translucent_;
    // The shadow cache (docs/DESIGN.md §5.11). What went into a depth layer: the same key, the same depths.
    struct AtlasKey {
        std::uint64_t fit_version = 0;      // FramePlan::fit_version
        std::uint64_t content_version = 0;  // bumped by set_scene, a new atlas texture and a caster's cut-out
        float caster_lod = 0.0f;
        bool caster_lod_per_tile = false;
        bool cull_back_faces = false;
        bool base_color_texture = true;  // masked casters cut out by their texture's alpha, or by the factor's
        AtlasMode atlas = AtlasMode::clip_distances;
        bool operator==(const AtlasKey&) const = default;
    };
    std::uint64_t content_version_ = 0;
    std::optional<AtlasKey> atlas_holds_static_;  // atlas_depth_ holds exactly the static casters for this key
    std::optional<AtlasKey> static_layer_holds_;  // static_depth_ holds them for this key
    std::optional<AtlasKey> last_key_;            // the last frame's key
    // The translucent layer (docs/DESIGN.md §5.15) over the opaque atlas of `opaque`, with the blended casters'
    // alphas of `version` (translucent_version_, bumped by set_material).
    struct TranslucentKey {
        AtlasKey opaque;
        std::uint64_t version = 0;
        bool operator==(const TranslucentKey&) const = default;
    };
    std::uint64_t translucent_version_ = 0;
    std::optional<TranslucentKey> translucent_holds_;
    gl::Texture static_depth_;  // the static casters' depths, atlas_depth_'s size and format
    int max_viewports_ = 1;

    gl::Texture environment_;
    PrefilteredEnvironment prefiltered_levels_;  // the levels' shininess and size (texels dropped)
    std::vector<gl::Texture> prefiltered_;       // per level, RGB32F lat-long
    // The GGX levels one above the other, RGB32F; level k's first row, width and height.
    gl::Texture ggx_level_texels_;
    gl::Texture ggx_mirror_;                      // the map without its compact sources (none: environment_)
    std::vector<CompactSource> compact_sources_;  // map space
    std::array<glm::ivec3, kGgxPrefilterLevels> ggx_level_rows_{};
    Hemisphere ggx_hemisphere_ = Hemisphere::full;
    gl::Texture dfg_;  // (scale, bias, diffuse, axis), RGBA32F over (n.v, roughness)
    // Drawn into target_: colour and depth with samples_ samples per pixel. At one sample color_ is target_'s
    // colour; with more, target_'s is multisample_color_, resolved into color_ through resolved_.
    int samples_ = 1;
    mutable bool warned_samples_ = false;
    int max_samples_ = 1;  // what the driver supports for RGBA32F colour and 32-bit float depth together
    gl::Texture color_, depth_, multisample_color_;
    gl::Framebuffer target_, resolved_;
    // Bit k of quarter q's mask: target_'s sample k lies in the pixel's quarter q (x = q & 1, y = q >> 1, from
    // the lower left); which quarters a fragment covers, for lobes taken over the pixel (glsl/pixel_footprint.glsl).
    std::array<GLuint, 4> sample_quarters_{1, 1, 1, 1};
    glm::vec2 sample_margin_{0.5f};  // how far target_'s samples can move and stay in their pixel
    glm::vec2 frame_shift_{0.0f};    // this frame's CameraView::jitter, clamped (pixels)
    glm::ivec2 screen_tiles_{0, 0};  // shader::size::screen_tile^2-pixel tiles of the target
    gl::Buffer tile_lists_;          // per screen tile: light count, light indices (shadow_tiles.comp)
    gl::Buffer caster_rect_buffer_;  // FramePlan::caster_rects
    // The shadowed-fraction pass (RenderSettings::shadow_rate other than fragment, docs/DESIGN.md §5.14):
    // one sample per pixel or per 2x2 pixels, with tile lists of its own.
    FractionTarget fraction_;
    int sun_cell_ = -1;  // sun_light() of the lights uploaded this frame (SUN_PER_PIXEL)
    glm::ivec2 fraction_tiles_{0, 0};
    gl::Buffer fraction_tile_lists_;
    gl::Texture fraction_filtered_;  // fraction_'s fraction and 1/w, filtered; made with fraction_filter
    gl::Framebuffer fraction_filter_target_;
    gl::Program fraction_filter_program_;
    FractionTarget refined_;        // ShadowRate::adaptive: fraction_ refined to one sample per pixel
    CasterTiles caster_tiles_;      // draw_casters: each caster's tiles by level, this draw's
    gl::Buffer atlas_tile_buffer_;  // caster_tiles_.tiles (shadow_atlas.vert's instance to tile)
};

}  // namespace envshadow::render
