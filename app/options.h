#pragma once
// The command line's shared vocabulary: the options several commands take, each with one spelling,
// range and help text, and how a value the engine parses in its own words gets the flag's name.
// README.md's command-line reference lists the same ranges.
#include <cstdint>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "core/error.h"
#include "core/tonemap.h"
#include "env/cells.h"
#include "env/environment.h"
#include "gl/timer.h"
#include "render/fs_sampler.h"
#include "render/render_settings.h"
#include "render/renderer.h"
#include "render/shadow_atlas_layout.h"
#include "scene/scene.h"

namespace envshadow::app {

// --width and --height: from one 16x16 screen tile up to core's image limit (kMaxImageWidth/Height).
inline constexpr int kMinImageSize = 16;

// The options of every command that renders (decompose takes the lights part only).
struct CommonOptions {
    std::string scene;                     // --scene: scene JSON or .gltf/.glb
    std::string env;                       // --env: overrides the scene's environment (decompose: the map)
    int lights = 128;                      // --lights: 1..kMaxLights
    std::string method = "lloyd";          // --method: a name of render::light_methods()
    std::uint64_t seed = 1;                // --seed
    int width = 960, height = 540;         // --width, --height: kMinImageSize..kMaxImageWidth/Height
    std::string backend = "egl";           // --backend: egl or osmesa
    std::string hemisphere = "auto";       // --hemisphere: full, upper, or auto (upper where the scene has a ground)
    std::string fs_importance = "blocks";  // --fs-importance (--method fs-gpu): blocks, full or WxH
};

// Which of CommonOptions a command takes.
struct CommonOptionSet {
    bool scene = true;           // --scene and --env overriding its map; false: --env alone, required
    bool scene_required = true;  // false: the command has a default scene
    bool lights = true;          // --lights and --method
    bool gpu_method = true;      // --method also takes fs-gpu (the lights sampled on the GPU every frame),
                                 // and --fs-importance configures it
    bool seed = true;
    bool size = true;  // --width, --height
    bool backend = true;
    bool hemisphere = true;  // --hemisphere full|upper|auto (decompose has its own: full|upper)
};

// Adds the options `set` names to `app`, stored in `options` (whose values are the defaults).
void add_common_options(CLI::App* app, CommonOptions* options, const CommonOptionSet& set);

// The directions to decompose for `scene` by --hemisphere: "auto" is the upper hemisphere where the
// scene has a ground (which hides every direction below its horizon, docs/DESIGN.md §3.1).
Hemisphere hemisphere_for(const std::string& choice, const Scene& scene);
// "full sphere" or "upper hemisphere", as the commands print it.
const char* hemisphere_words(Hemisphere hemisphere);

// --fs-importance, the GPU sampler's importance map (docs/FS_GPU.md): "blocks" (the default) the CPU
// method fs's blocks and rules, whose lights are fs's; "full" the environment's own resolution, or "WxH"
// (W a multiple of 16), both with the rules for a chosen size. UsageError naming the flag otherwise.
render::FsSamplerOptions parse_fs_importance(const std::string& text);
// The same, and a WxH that fits in `map`.
render::FsSamplerOptions fs_sampler_options(const std::string& text, const EnvironmentMap& map);

// A number that is neither NaN nor infinite (CLI::Range lets NaN through: every comparison with it fails).
const CLI::Validator& finite_number();

// --time: the animation time in seconds.
void add_time_option(CLI::App* app, double* time);

// --tile and --depth-bits: the shadow atlas of render and bench.
void add_atlas_options(CLI::App* app, int* tile, int* depth_bits);

// --tile-sizes share|sqrt|uniform, for render, bench and view: power-of-two tiles sized by the
// light's luminance share (default) or its square root within the budget of N --tile^2 texels, or
// every tile --tile^2.
void add_tile_sizes_option(CLI::App* app, std::string* value);
render::TileSizing tile_sizing(const std::string& value);
// "uniform", or e.g. "share: 128^2 to 1024^2, 8388608 texels of a budget of 128 x 256^2", as the
// commands print it.
std::string tile_sizes_words(const render::AtlasLayout& layout);

// --pass-timing, for the commands that render; pass_timing() reads the value.
void add_pass_timing_option(CLI::App* app, std::string* value);
gl::PassTiming pass_timing(const std::string& value, bool software_rasteriser);

// --baseline, --caster-lod, --prepass: issue 10's optimisations, for render and bench.
struct OptimisationFlags {
    bool baseline = false;
    std::string caster_lod, prepass;  // empty: the default
};
void add_optimisation_options(CLI::App* app, OptimisationFlags* flags);
// `settings` with the flags applied (baseline first); UsageError naming the flag for a bad value.
render::RenderSettings apply(const OptimisationFlags& flags, render::RenderSettings settings);

// --shading cells|ratio (render, bench, view): the paper's per-cell sum, or the ratio estimator with the
// unshadowed reflection from the prefiltered map (docs/DESIGN.md §4.1).
void add_shading_option(CLI::App* app, std::string* value);
render::ShadingMode shading_mode(const std::string& value);
// --msaa 1|2|4|8 (render, bench, view): samples per pixel of the shading target, resolved before tone
// mapping (render::RenderSettings::msaa). The commands' default.
inline constexpr int kDefaultMsaa = 4;
void add_msaa_option(CLI::App* app, int* samples);
// --tonemap aces|agx|neutral|linear (render, reference, view): the display transform of 8-bit output
// (core/tonemap.h); EXR stays linear.
void add_tonemap_option(CLI::App* app, std::string* value);
// --shadows hard|soft (render, bench, view): each cell's 2x2 shadow lookup, or its penumbra from the cell's
// cap (docs/DESIGN.md §5.9). kDefaultShadows: RenderSettings' default, by name.
inline const std::string kDefaultShadows{render::to_string(render::RenderSettings{}.shadows)};
void add_shadows_option(CLI::App* app, std::string* value);
render::ShadowMode shadow_mode(const std::string& value);
ToneMap tone_map_option(const std::string& value);
// The directions that reach the objects of `scene`: the upper hemisphere where a ground hides the rest
// (as in the reference), whatever --hemisphere the cells were cut from. Ratio shading prefilters these.
Hemisphere visible_hemisphere(const Scene& scene);
// The map prefiltered for ratio shading over `hemisphere` (visible_hemisphere), uploaded to `renderer`;
// prints its size and time on one line when `print`.
void prefilter_for(render::Renderer& renderer, const EnvironmentMap& map, Hemisphere hemisphere, bool print);
// renderer.set_scene(scene), with a progress line on a terminal for a million triangles or more (the
// shadow-caster LOD takes seconds per million); `print`: a line with the triangles and the seconds.
void set_scene_for(render::Renderer& renderer, const Scene& scene, bool print);

// `parse()`, and a UsageError it throws (in the engine's words) prefixed by `flag`:
// "--atlas: 'x' is not one of clip-distances, viewport-array, per-tile".
template <class Parse>
auto naming_flag(std::string_view flag, Parse&& parse) {
    try {
        return parse();
    } catch (const UsageError& e) {
        throw UsageError(std::string(flag) + ": " + e.what());
    }
}

}  // namespace envshadow::app
