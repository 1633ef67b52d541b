#pragma once
// What one frame draws, decided on the CPU before any GL call: each object's transforms and shading
// inputs, each light's orthographic projection fitted to the shadow casters (Barsi et al. §2.2: one
// depth map per cell) with its tile in the atlas and its biases, each caster's rectangle in each
// light's tile (glsl/shadow_tiles.comp), and the unshadowed sum of the flat receivers. Plain C++, no
// GL: tested headless (tests/render/frame_plan_test.cpp). Renderer uploads the plan and draws it.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "render/lights.h"
#include "render/render_settings.h"
#include "render/shadow_atlas_layout.h"
#include "scene/scene.h"

namespace envshadow::render {

// Where the camera is and the image it makes.
struct CameraView {
    glm::mat4 view_from_world{1.0f};
    glm::mat4 clip_from_view{1.0f};
    glm::vec3 eye{0.0f};
    int width = 0;
    int height = 0;
    // The image moved by this many pixels (x right, y up), no farther than keeps every sample in its pixel
    // (sample_margin; Renderer::render clamps it). Frames moved by subpixel_jitter()'s shifts and averaged
    // resolve edges in finer steps than one frame's samples (docs/DESIGN.md §5.16).
    glm::vec2 jitter{0.0f};
};

// The scene's camera for an image of width x height (near and far planes from the scene bounds).
CameraView camera_view(const Scene& scene, int width, int height, double time = 0.0);

// `view` with its image moved by `pixels` (x right, y up): the projection followed by that shift.
CameraView shifted_by_pixels(const CameraView& view, glm::vec2 pixels);

// How far (pixels, along x and y) samples at these positions in the pixel ([0, 1]^2) can all move either way and
// stay in their pixel: 1/2 for one sample at the centre, 1/8 for GL's standard four.
glm::vec2 sample_margin(std::span<const glm::vec2> sample_positions);

// `count` shifts for frames averaged into one image (docs/DESIGN.md §5.16): a rank-1 lattice over the box of
// sample_margin, its generator the one that keeps the shifts farthest apart. Each sample then sweeps a box
// about its own position, one shift in each of `count` strata along either axis; where the frame's samples hold
// one each of `samples` strata along x and along y (GL's standard patterns), the frames' hold one each of
// count x samples: an edge along either axis is resolved in steps of 1 / (count x samples). The shifts' mean is
// 0. One frame: no shift.
std::vector<glm::vec2> subpixel_jitter(int count, std::span<const glm::vec2> sample_positions);

// Texels between the casters and a tile's border (whatever the tile's size, its texels are the
// atlas's): the wide PCF reaches 1.5 texels from its centre.
inline constexpr float kTileMarginTexels = 3.0f;
// Caster rectangles per light at most; with more casters one rectangle, the whole tile, stands for all.
inline constexpr int kMaxCasterRects = 16;

// Whether the screen-tile light lists run (glsl/shadow_tiles.comp): they need the depth pre-pass.
bool uses_tile_lists(const RenderSettings& settings);

// A cell's penumbra in its tile's texels (x, y) per unit of depth (0..1) between blocker and receiver:
// tan r_i times the tile's depth range in the world times its texels per world unit along x and y
// (docs/DESIGN.md §5.9). LightRecord::bias.zw.
glm::vec2 penumbra_texels_per_depth(const glm::mat4& clip_from_world, int tile_size, float cos_radius);

// One drawn object as the plan sees it.
struct PlannedObject {
    Object object;                                 // transform, animation, material (the mesh pointer is not used)
    glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};  // its mesh's box, object space
    std::optional<glm::vec3> flat_normal;          // its mesh is a plane with this normal (object space)
};

// The variants of glsl/shade.frag.
enum class ShadeProgram {
    full,
    diffuse_only,   // DIFFUSE_ONLY: k_s = 0
    flat_receiver,  // FLAT_RECEIVER: a diffuse plane, its unshadowed sum from the CPU
    // METALLIC_ROUGHNESS: ratio shading's unshadowed part by glTF's BRDF (Material::metallic_roughness); the
    // renderer draws it with `full` while it has no GGX levels.
    metallic_roughness,
};

struct ObjectFrame {
    glm::mat4 world_from_object{1.0f};
    glm::mat3 world_normal_from_object{1.0f};  // inverse transpose
    bool casts_shadows = true;
    ShadeProgram program = ShadeProgram::full;
    glm::vec3 k_d{0.0f};  // rho_d / pi
    float k_s = 0.0f;     // rho_s (n + 2) / (2 pi)
    float shininess = 1.0f;
    glm::vec3 unshadowed{0.0f};  // flat_receiver: sum of L~_i a_i, the same for all its pixels
    // Ratio shading by glTF's BRDF, the unshadowed part and the cells' weights (k_d, k_s and shininess stay
    // its Phong stand-in, for cells shading).
    std::optional<MetallicRoughness> metallic_roughness;
    glm::vec3 emission{0.0f};         // Material::emission, times the emission texture in shade.frag
    float occlusion_strength = 1.0f;  // Material::occlusion_strength (the texture is white without one)
    float normal_scale = 0.0f;        // Material::normal_scale where the normal map is drawn, else 0
    // Material::masked(): cut out where base_alpha times the base-colour texture's alpha < alpha_cutoff; a
    // cutoff of 0 cuts nothing. Material::blended(): laid over what is behind it by that alpha, after the
    // opaque objects; as a caster in the atlas's translucent layer, passing 1 - alpha of the light.
    float base_alpha = 1.0f, alpha_cutoff = 0.0f;
    bool blended = false;
    bool masked() const { return alpha_cutoff > 0.0f; }
    bool alpha_in_atlas() const { return masked() || blended; }  // its casters read texture coordinates
};

struct FramePlan {
    std::vector<ObjectFrame> objects;  // one per PlannedObject
    std::vector<LightRecord> lights;   // one per light: the GPU's light buffer
    // Per light, caster_rects_per_light rectangles in its clip space (xy lower left, zw upper right),
    // each caster's box widened by 2 texels; never empty (one zero rectangle without lights).
    std::vector<glm::vec4> caster_rects;
    int caster_rects_per_light = 1;
    std::vector<float> texel_world;  // per light, its tile's texel (world units, the larger axis)
    float min_texel_world = 0.0f;    // smallest atlas texel of the fits (world units); 0 without lights
    float receiver_pad = 0.0f;       // tile lists: how far the receivers' bounds are pushed out (world)
    // Changes whenever a light's projection or tile differs from the last plan's (the shadow cache's
    // key, docs/DESIGN.md §5.11); the same number while every fit stays the same.
    std::uint64_t fit_version = 0;
};

// Samples per period of a moving caster's box for the fits over the animation (ShadowFit::animation).
inline constexpr int kAnimationFitSamples = 32;

// World points whose boxes, in any light's frame, hold every shadow caster of `objects` at every time
// (ShadowFit::animation): the 8 corners of each caster that does not move, and for each that moves its
// box's corners (a deforming object's box of its pose at that time) at kAnimationFitSamples times over
// its period (Object::motion_period), each pushed out to a cube as wide as the
// farthest a corner travels between two samples (so the times between samples stay inside).
std::vector<glm::vec3> animation_caster_points(std::span<const PlannedObject> objects);

// The unshadowed diffuse sum sum_i L~_i k_d max(n . w_i, 0) of a plane with normal `normal`
// (FLAT_RECEIVER: shade.frag's centre sample, DiffuseMode::center), accumulated in double.
glm::vec3 flat_receiver_sum(std::span<const LightRecord> lights, const glm::vec3& k_d, const glm::vec3& normal);

// Keeps the objects and the lights between frames and rewrites one plan per frame in place (its
// vectors keep their storage).
class FramePlanner {
public:
    void set_objects(std::vector<PlannedObject> objects);
    std::span<const PlannedObject> objects() const { return objects_; }
    void set_material(std::size_t object, const Material& material) { objects_.at(object).object.material = material; }
    // A deforming object's box at this frame's pose (object space; glTF skins and morphs).
    void set_bounds(std::size_t object, const glm::vec3& lo, const glm::vec3& hi) {
        objects_.at(object).bounds_min = lo;
        objects_.at(object).bounds_max = hi;
    }
    // World-space lights (select_lights); their frames are made here, once.
    void set_lights(std::span<const WorldLight> lights);
    std::size_t light_count() const { return lights_.size(); }

    // The frame at animation time `time` seen from `view`, for the atlas `layout`.
    const FramePlan& plan(double time, const CameraView& view, const AtlasLayout& layout,
                          const RenderSettings& settings);
    const FramePlan& last() const { return plan_; }

private:
    void place_objects(double time);
    void fit_lights(const AtlasLayout& layout, const RenderSettings& settings);
    void fit_caster_rects(const AtlasLayout& layout, const RenderSettings& settings);
    void shade_objects(const CameraView& view, const RenderSettings& settings);

    std::vector<PlannedObject> objects_;
    std::vector<WorldLight> lights_;
    std::vector<LightFrame> frames_;
    std::vector<LightNeighbourhood> neighbourhoods_;  // light_neighbourhoods of lights_
    std::vector<glm::vec3> caster_points_;            // 8 box corners per shadow caster, world space
    std::vector<glm::vec3> animation_points_;         // animation_caster_points(objects_)
    // ShadowFit::animation: the fits are the same every frame while the lights and tile sizes are.
    std::vector<OrthographicFit> animation_fits_;
    std::vector<int> animation_fit_tile_sizes_;
    std::vector<glm::mat4> previous_fits_;  // the last plan's clip_from_world and tile, per light
    std::vector<glm::vec4> previous_tiles_;
    FramePlan plan_;
};

}  // namespace envshadow::render
