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
#include "setting_options.h"

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
inline constexpr std::string_view kAutoHemisphere = "auto";
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

// "uniform", or e.g. "share: 128^2 to 1024^2, 8388608 texels of a budget of 128 x 256^2", as the
// commands print it.
std::string tile_sizes_words(const render::AtlasLayout& layout);

// --pass-timing, for the commands that render; pass_timing() reads the value.
void add_pass_timing_option(CLI::App* app, std::string* value);
gl::PassTiming pass_timing(const std::string& value, bool software_rasteriser);

// --tonemap aces|agx|neutral|linear (render, reference, view): the display transform of 8-bit output
// (core/tonemap.h); EXR stays linear.
void add_tonemap_option(CLI::App* app, std::string* value);
ToneMap tone_map_option(const std::string& value);
// The directions that reach the objects of `scene`: the upper hemisphere where a ground hides the rest
// (as in the reference), whatever --hemisphere the cells were cut from. Ratio shading prefilters these.
Hemisphere visible_hemisphere(const Scene& scene);

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
