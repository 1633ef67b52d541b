// `envshadow render`: an image of a scene offscreen (EGL or OSMesa) to PNG and/or EXR, the mean of --accumulate
// frames with their samples moved within the pixel (docs/DESIGN.md §5.16). Prints the
// decomposition time, the frame's GPU time per pass and the shadow atlas's size. With --frames F
// the times are medians over F frames (after one warm-up frame); with --atlas all every frame is
// drawn once per way of drawing the atlas, interleaved, so their times compare in one run.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench_stats.h"
#include "commands.h"
#include "core/error.h"
#include "core/image.h"
#include "env/cells.h"
#include "env/environment.h"
#include "gl/context.h"
#include "inputs.h"
#include "render/light_source.h"
#include "render/renderer.h"
#include "session.h"

namespace envshadow::app {
namespace {

// --atlas all: every frame drawn once per way of drawing the atlas.
constexpr ExtraValue kEveryAtlasMode{"atlas", "all", "each of them, interleaved, to time them in one run"};

constexpr const char* kSamplingWall = "sampling wall";  // the per-frame light source's, among the passes

// Frames averaged into the image, each with its samples moved within the pixel by render::subpixel_jitter
// (docs/DESIGN.md §5.16): edges against a bright sky resolved in finer steps than one frame's samples; past
// eight, little more.
constexpr int kDefaultAccumulate = 8;

struct RenderOptions {
    CommonOptions common;     // --scene, --env, --lights, --method, --seed, --width, --height, --backend
    SettingOptions settings;  // --tile, --pcf, --shading, ... (render::setting_table()), --baseline
    std::string out, exr;
    int frames = 1;
    int accumulate = kDefaultAccumulate;
    std::string tonemap = "aces";
    double time = 0.0;
    std::string pass_timing = "auto";
    bool per_tile_atlas = false, no_background = false;  // short for --atlas per-tile, --background off
};

// The settings, and the atlas modes to draw each frame: the one chosen, or all three with --atlas all.
struct RenderPlan {
    render::RenderSettings settings;
    std::vector<render::AtlasMode> atlas_modes;
};

RenderPlan plan_from(const RenderOptions& o) {
    SettingOptions given = o.settings;
    const auto atlas = given.given.find("atlas");
    const bool every_atlas_mode = atlas != given.given.end() && atlas->second == kEveryAtlasMode.value;
    if (o.per_tile_atlas && atlas != given.given.end())
        throw UsageError("--per-tile-atlas and --atlas exclude each other");
    if (every_atlas_mode) given.given.erase(atlas);
    if (o.per_tile_atlas) given.given["atlas"] = to_string(render::AtlasMode::per_tile);
    if (o.no_background) given.given["background"] = "off";
    RenderPlan plan{settings_from(given, command_defaults()), {}};
    if (every_atlas_mode)
        for (const auto& [mode, name] : render::enum_names(render::AtlasMode{})) plan.atlas_modes.push_back(mode);
    else
        plan.atlas_modes = {plan.settings.atlas};
    return plan;
}

int run_render(const RenderOptions& o) {
    if (o.out.empty() && o.exr.empty()) throw UsageError("render: give --out OUT.png and/or --exr OUT.exr");
    const CommonOptions& c = o.common;
    const RenderPlan plan = plan_from(o);
    render::RenderSettings settings = plan.settings;
    const std::vector<render::AtlasMode>& modes = plan.atlas_modes;
    settings.atlas = modes.front();

    const Inputs inputs = load_inputs(c.scene, c.env, o.time);
    const Scene& scene = inputs.scene;
    const EnvironmentMap& map = inputs.map;

    auto context = gl::create_context(gl::parse_backend(c.backend));
    RenderSession session(inputs, settings, pass_timing(o.pass_timing, context->is_software()), Report::print);
    // fs-gpu: Floyd-Steinberg samples of the environment texture made on the GPU every frame
    // (docs/FS_GPU.md), instead of a decomposition at load time.
    const render::LightMethod& method = render::light_method(c.method);
    render::LightSource lights = render::make_light_source(
        method, map, c.lights, c.seed, hemisphere_for(c.hemisphere, scene),
        method.kind == render::LightSourceKind::gpu_fs ? fs_sampler_options(c.fs_importance, map)
                                                       : render::FsSamplerOptions{});
    lights.attach(session.renderer());
    const std::vector<glm::vec2> jitter = render::subpixel_jitter(o.accumulate, session.renderer().sample_positions());
    render::CameraView view = render::camera_view(scene, c.width, c.height, o.time);
    view.jitter = jitter.front();

    // Per mode and pass, the GPU milliseconds of every measured frame.
    std::map<render::AtlasMode, std::map<std::string, std::vector<double>>> times;
    render::FrameStats stats;
    std::optional<Image> image;
    const int warmup = o.frames > 1 ? 1 : 0;
    for (int frame = 0; frame < warmup + o.frames; ++frame)
        for (render::AtlasMode mode : modes) {
            settings.atlas = mode;
            session.set_settings(settings);
            const auto start = std::chrono::steady_clock::now();
            stats = session.render(lights, o.time, view);  // returns after the GPU's timer results are in
            if (lights.per_frame() && frame >= warmup) times[mode][kSamplingWall].push_back(lights.sampling_ms());
            const std::chrono::duration<double, std::milli> wall = std::chrono::steady_clock::now() - start;
            if (frame >= warmup) {
                for (const gl::PassTime& pass : stats.passes) times[mode][pass.pass].push_back(pass.milliseconds);
                times[mode]["frame wall"].push_back(wall.count());
            }
            if (!image) image = session.renderer().read_back();  // the first mode's first frame
        }
    // The image: the mean of the first frame and one more per further point of the jitter, in linear HDR.
    if (o.accumulate > 1) {
        if (modes.size() > 1) {  // --atlas all left the last mode set: the image is the first's
            settings.atlas = modes.front();
            session.set_settings(settings);
        }
        for (std::size_t k = 1; k < jitter.size(); ++k) {
            view.jitter = jitter[k];
            session.render(lights, o.time, view);
            const Image frame = session.renderer().read_back();
            for (std::size_t i = 0; i < image->pixels.size(); ++i) image->pixels[i] += frame.pixels[i];
        }
        for (glm::vec4& pixel : image->pixels) pixel /= float(jitter.size());
    }

    std::printf("scene %s, %dx%d, %s on %s\n", c.scene.c_str(), c.width, c.height,
                std::string(gl::to_string(context->backend())).c_str(), context->renderer().c_str());
    if (const render::FsSampler* sampler = lights.sampler()) {
        const render::FsCounts counts = sampler->read_counts();
        std::printf("%s: %u lights of %u samples from a %dx%d importance map of %s, %s, every frame, %.2f ms wall",
                    std::string(lights.method().name()).c_str(), counts.light_count, counts.samples,
                    sampler->importance_size().x, sampler->importance_size().y, map.source.c_str(),
                    hemisphere_words(lights.hemisphere()), summarize(times[modes.front()][kSamplingWall]).median);
        if (lights.lights_folded() > 0)
            std::printf(" (%d beyond the %d the renderer takes folded into the brightest)", lights.lights_folded(),
                        kMaxLights);
        std::printf("\n");
    } else {
        const Decomposition& d = lights.decomposition();
        std::printf("decomposition: %s, %zu cells of %dx%d %s, %s, %.3f s\n", std::string(to_string(d.method)).c_str(),
                    d.cells.size(), d.width, d.height, map.source.c_str(), hemisphere_words(d.hemisphere), d.seconds);
    }
    std::printf("shading: %s (specular %s, cap %s, diffuse %s), shadows %s\n",
                std::string(to_string(settings.shading)).c_str(), std::string(to_string(settings.specular)).c_str(),
                std::string(to_string(settings.cap)).c_str(), std::string(to_string(settings.diffuse)).c_str(),
                std::string(to_string(settings.shadows)).c_str());
    std::printf("msaa: %d samples per pixel", session.renderer().samples());
    if (o.accumulate > 1) std::printf(", %d frames jittered within the pixel averaged", o.accumulate);
    std::printf("\n");
    std::printf("lights: %d drawn, %d below the ground and %d negligible skipped\n", stats.lights,
                stats.lights_below_ground, stats.lights_negligible);
    const bool uniform_tiles = stats.atlas.sizing == render::TileSizing::uniform;
    std::printf("atlas: %d tiles %s %d^2 in %dx%d, %d-bit depth: %zu bytes\n", stats.atlas.tile_count,
                uniform_tiles ? "of" : "in the texels of", stats.atlas.tile_size, stats.atlas.width(),
                stats.atlas.height(), settings.depth_bits, stats.atlas_bytes);
    std::printf("tile sizes: %s%s\n", tile_sizes_words(stats.atlas).c_str(),
                lights.per_frame() && settings.tile_sizing != render::TileSizing::uniform
                    ? " (lights sampled every frame keep uniform tiles)"
                    : "");
    for (render::AtlasMode mode : modes) {
        std::printf("gpu ms (%s atlas%s%s):", std::string(to_string(mode)).c_str(),
                    o.frames > 1 ? (", median of " + std::to_string(o.frames) + " frames").c_str() : "",
                    session.renderer().pass_timing() == gl::PassTiming::synchronous ? ", each pass waited for" : "");
        double total = 0.0;
        for (const gl::PassTime& pass : stats.passes) {
            const double ms = summarize(times[mode][pass.pass]).median;
            total += ms;
            std::printf(" %s %.2f,", pass.pass.c_str(), ms);
        }
        // llvmpipe times its queries in the rasteriser threads, after the draw calls' vertex work:
        // the wall-clock time of the whole frame (submission to results) says what a frame costs.
        std::printf(" total %.2f; frame wall-clock %.2f\n", total, summarize(times[mode]["frame wall"]).median);
    }

    if (!o.exr.empty()) {
        write_exr(o.exr, *image);
        std::printf("wrote %s\n", o.exr.c_str());
    }
    if (!o.out.empty()) {
        // The PNG is for looking at: opaque where the environment was drawn behind the objects (the
        // EXR keeps alpha as the object mask).
        if (settings.background)
            for (glm::vec4& pixel : image->pixels) pixel.a = 1.0f;
        write_png(o.out, tonemap_to_srgb8(*image, scene.environment.exposure_stops, tone_map_option(o.tonemap)));
        std::printf("wrote %s\n", o.out.c_str());
    }
    return 0;
}

}  // namespace

Command add_render_command(CLI::App& parent) {
    auto o = std::make_shared<RenderOptions>();
    CLI::App* app = parent.add_subcommand("render", "Render an image offscreen to PNG and/or EXR");
    add_common_options(app, &o->common, CommonOptionSet{});
    add_pass_timing_option(app, &o->pass_timing);
    add_time_option(app, &o->time);
    app->add_option("--out", o->out, "PNG to write (exposure, --tonemap, sRGB)");
    add_tonemap_option(app, &o->tonemap);
    app->add_option("--exr", o->exr, "EXR to write (linear; alpha 1 on objects, 0 on the background)");
    add_setting_options(app, &o->settings, command_defaults(), std::span(&kEveryAtlasMode, 1));
    app->add_flag("--per-tile-atlas", o->per_tile_atlas, "Short for --atlas per-tile");
    app->add_flag("--no-background", o->no_background, "Short for --background off: transparent black");
    app->add_option("--frames", o->frames, "Frames to render; GPU times are their medians")
        ->check(CLI::Range(1, 10000));
    app->add_option("--accumulate", o->accumulate,
                    "Frames averaged into the image, the pixel's samples moved within it from one to the next "
                    "(1: one frame)")
        ->check(CLI::Range(1, 32))
        ->capture_default_str();
    return {app, [o] { return run_render(*o); }};
}

}  // namespace envshadow::app
