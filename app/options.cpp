#include "options.h"

#include <cmath>
#include <cstdio>
#include <vector>

#include "core/image.h"
#include "env/cells.h"
#include "gl/context.h"
#include "render/light_source.h"
#include "render/shader_interface.h"
#include "render/shadow_atlas_layout.h"
#include "variants.h"

namespace envshadow::app {

void add_common_options(CLI::App* app, CommonOptions* o, const CommonOptionSet& set) {
    if (set.scene) {
        CLI::Option* scene =
            app->add_option("--scene", o->scene,
                            set.scene_required ? "Scene JSON, or a .gltf/.glb"
                                               : "Scene JSON, or a .gltf/.glb (default: assets/scenes/default.json)");
        if (set.scene_required) scene->required();
        app->add_option("--env", o->env, "Environment map (.exr, .hdr or builtin:...), overriding the scene's");
    } else {
        app->add_option("--env", o->env, "Environment: an .exr or .hdr lat-long map, or builtin:constant, builtin:sky")
            ->required();
    }
    if (set.lights) {
        app->add_option("--lights", o->lights, "Number of cells (lights) N")->check(CLI::Range(1, kMaxLights));
        std::vector<std::string> names;
        std::string help;
        for (const render::LightMethod& method : render::light_methods()) {
            if (method.kind == render::LightSourceKind::gpu_fs && !set.gpu_method) continue;
            names.emplace_back(method.name());
            help += (help.empty() ? "" : "; ") + names.back() + ": " + std::string(method.help);
        }
        app->add_option("--method", o->method, help)->check(CLI::IsMember(names));
        if (set.gpu_method)
            app->add_option("--fs-importance", o->fs_importance,
                            "fs-gpu's importance map: blocks (default: the CPU method fs's), full (the "
                            "environment's size) or WxH")
                ->type_name("blocks|full|WxH");
    }
    if (set.seed)
        app->add_option("--seed", o->seed, "Random seed (of the decomposition's sites; of the reference's samples)");
    if (set.size) {
        app->add_option("--width", o->width, "Image width")->check(CLI::Range(kMinImageSize, kMaxImageWidth));
        app->add_option("--height", o->height, "Image height")->check(CLI::Range(kMinImageSize, kMaxImageHeight));
    }
    if (set.backend)
        app->add_option("--backend", o->backend, "Headless OpenGL context")
            ->check(CLI::IsMember(gl::headless_backend_names()));
    if (set.hemisphere) {
        std::vector<std::string> names = enum_value_names<Hemisphere>();
        names.emplace_back(kAutoHemisphere);
        app->add_option("--hemisphere", o->hemisphere,
                        "Directions the lights come from: full (the whole sphere), upper (above the horizon), or "
                        "auto (default: upper where the scene has a ground, else full)")
            ->check(CLI::IsMember(names));
    }
}

render::FsSamplerOptions parse_fs_importance(const std::string& text) {
    render::FsSamplerOptions options;
    if (text == "blocks") return options;  // FsWeighting::adaptive_blocks, the default
    options.weighting = render::FsWeighting::warmup_matched;
    if (text == "full") {
        options.importance_width = options.importance_height = 0;  // the environment's
        return options;
    }
    int width = 0, height = 0;
    char x = 0, rest = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || x != 'x' || width < 16 ||
        height < 1 || width % render::shader::size::fs_scan_run != 0)
        throw UsageError("--fs-importance " + text + ": give blocks, full or WxH with W a multiple of " +
                         std::to_string(render::shader::size::fs_scan_run));
    options.importance_width = width;
    options.importance_height = height;
    return options;
}

render::FsSamplerOptions fs_sampler_options(const std::string& text, const EnvironmentMap& map) {
    const render::FsSamplerOptions options = parse_fs_importance(text);
    if (options.weighting != render::FsWeighting::adaptive_blocks &&
        (options.importance_width > map.width || options.importance_height > map.height))
        throw UsageError("--fs-importance " + text + ": at most the map's " + std::to_string(map.width) + "x" +
                         std::to_string(map.height));
    return options;
}

const CLI::Validator& finite_number() {
    static const CLI::Validator validator(
        [](std::string& input) {
            double value = 0.0;
            if (!CLI::detail::lexical_cast(input, value) || !std::isfinite(value))
                return "Value " + input + " is not a finite number";
            return std::string();
        },
        "FINITE");
    return validator;
}

void add_time_option(CLI::App* app, double* time) {
    app->add_option("--time", *time, "Animation time in seconds (builtin:sky's sun: one hour per second)")
        ->check(finite_number());
}

std::string tile_sizes_words(const render::AtlasLayout& layout) {
    if (layout.sizing == render::TileSizing::uniform) return "uniform";
    return std::string(render::to_string(layout.sizing)) + ": " + std::to_string(layout.smallest_tile()) + "^2 to " +
           std::to_string(layout.largest_tile()) + "^2, " + std::to_string(layout.tile_texels()) +
           " texels of a budget of " + std::to_string(layout.tile_count) + " x " + std::to_string(layout.tile_size) +
           "^2";
}

void add_pass_timing_option(CLI::App* app, std::string* value) {
    app->add_option("--pass-timing", *value,
                    "auto (default: wait on a software rasteriser, queries on a GPU), queries (GL_TIME_ELAPSED) or "
                    "wait (glFinish around each pass)")
        ->check(CLI::IsMember(gl::pass_timing_choices()));
}

gl::PassTiming pass_timing(const std::string& value, bool software_rasteriser) {
    return naming_flag("--pass-timing", [&] { return gl::parse_pass_timing(value, software_rasteriser); });
}

void add_tonemap_option(CLI::App* app, std::string* value) {
    app->add_option("--tonemap", *value,
                    "Tone map of the PNG: aces (filmic, the default), agx, neutral (Khronos PBR Neutral) or "
                    "linear (a clamp); EXR stays linear")
        ->check(CLI::IsMember(enum_value_names<ToneMap>()));
}

ToneMap tone_map_option(const std::string& value) {
    return naming_flag("--tonemap", [&] { return parse_enum<ToneMap>(value); });
}

Hemisphere visible_hemisphere(const Scene& scene) {
    return scene.has_ground ? Hemisphere::upper : Hemisphere::full;
}

Hemisphere hemisphere_for(const std::string& choice, const Scene& scene) {
    if (choice == kAutoHemisphere) return visible_hemisphere(scene);
    return naming_flag("--hemisphere", [&] { return parse_enum<Hemisphere>(choice); });
}

const char* hemisphere_words(Hemisphere hemisphere) {
    return hemisphere == Hemisphere::upper ? "upper hemisphere" : "full sphere";
}

}  // namespace envshadow::app
