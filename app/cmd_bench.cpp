// `envshadow bench`: frame times of a scene, headless. Warm-up frames, then F timed frames with the
// animation running (the shadow atlas really is redrawn every frame); per-pass GPU times from timer
// queries and the wall time of each frame; medians and 95th percentiles. `--sweep` repeats the run
// for each setting, so the growth of the cost with N (or resolution, or tile size) can be read off.
// `--variants "baseline;optimised;…"` renders every timed frame once per variant (one renderer
// each, interleaved frame by frame), so their ratios are measured under the same machine load.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_stats.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/log.h"
#include "env/cells.h"
#include "env/environment.h"
#include "gl/context.h"
#include "render/embedded_shaders.h"
#include "render/fs_sampler.h"
#include "render/renderer.h"
#include "scene/scene.h"

namespace envshadow::app {
namespace {

struct BenchOptions {
    std::string scene, env, method = "lloyd", backend = "egl", json, sweep, atlas = "clip-distances", variants,
                            pass_timing = "auto";
    std::string fs_importance = "256x128";  // fs-gpu: the importance map, WxH or "full" (the environment's)
    OptimisationFlags optimisations;
    int lights = 128, frames = 100, warmup = 10, width = 1280, height = 720, tile = 256, depth_bits = 16;
    double time_step = 1.0 / 60.0;  // animation seconds per frame
    std::uint64_t seed = 1;
};

struct Row {
    SweepPoint point;
    std::string variant;  // "" without --variants
    double ratio = 1.0;   // median frame time over the first variant's (same sweep point)
    std::size_t atlas_triangles = 0;
    int lights = 0, lights_drawn = 0, tile = 0, width = 0, height = 0;
    double decompose_ms = 0.0;
    TimeSummary frame_ms;                       // wall time per frame, CPU and GPU
    std::vector<std::string> pass_order;        // as the renderer reports them (pipeline order)
    std::map<std::string, TimeSummary> passes;  // GPU time per pass
    TimeSummary gpu_ms;                         // sum of the passes per frame
    std::size_t gpu_frames = 0;                 // frames whose every pass had a valid reading (gpu_ms's samples)
};

struct Variant {
    std::string label;
    render::RenderSettings settings;
    std::unique_ptr<render::Renderer> renderer;
};

// A ground hides every direction below the horizon: only the upper hemisphere is decomposed.
Hemisphere visible_hemisphere(const Scene& scene) {
    return scene.has_ground ? Hemisphere::upper : Hemisphere::full;
}

// One row per variant for this sweep point; the variants' frames are interleaved.
// With `sampler` (fs-gpu) the lights are sampled on the GPU before every frame; the sampling is part of
// the frame's wall time and reported as its own column (wall time, up to the lights' read-back).
std::vector<Row> measure(const BenchOptions& o, const SweepPoint& point, const Scene& scene, const EnvironmentMap& map,
                         std::vector<Variant>& variants, std::map<int, Decomposition>& decompositions,
                         render::FsSampler* sampler) {
    Row common;
    common.point = point;
    common.lights = point.lights ? point.lights : o.lights;
    common.width = point.width ? point.width : o.width;
    common.height = point.height ? point.height : o.height;

    auto found = decompositions.find(common.lights);
    if (found == decompositions.end())
        found = decompositions
                    .emplace(common.lights, sampler ? Decomposition{}
                                                    : decompose(map, {.method = parse_method(o.method),
                                                                      .lights = common.lights,
                                                                      .seed = o.seed,
                                                                      .hemisphere = visible_hemisphere(scene)}))
                    .first;
    common.decompose_ms = found->second.seconds * 1000.0;

    std::vector<Row> rows(variants.size(), common);
    struct Samples {
        std::vector<double> frame_ms, gpu_ms;
        std::map<std::string, std::vector<double>> pass_ms;
    };
    std::vector<Samples> samples(variants.size());
    for (std::size_t v = 0; v < variants.size(); ++v) {
        render::RenderSettings settings = variants[v].settings;
        if (point.tile) settings.tile_size = point.tile;
        variants[v].renderer->set_settings(settings);
        variants[v].renderer->set_lights(found->second.cells);
        rows[v].variant = variants[v].label;
        rows[v].tile = settings.tile_size;
    }
    double time = 0.0;
    for (int frame = 0; frame < o.warmup + o.frames; ++frame, time += o.time_step) {
        const render::CameraView view = render::camera_view(scene, common.width, common.height, time);
        for (std::size_t v = 0; v < variants.size(); ++v) {
            const auto start = std::chrono::steady_clock::now();
            std::vector<gl::PassTime> sampling;
            if (sampler) {  // wall time: GL_TIME_ELAPSED around the sampler's compute and transform feedback is
                            // unreliable on llvmpipe and spoils the renderer's next query (docs/PERFORMANCE.md)
                sampler->sample(
                    variants[v].renderer->environment_texture(),
                    render::FsSampleRequest{.samples = common.lights, .upper_hemisphere = scene.has_ground});
                variants[v].renderer->set_lights(sampler->read_lights());  // waits for the sampler
                sampling.push_back(
                    {render::kFsSamplingPass,
                     std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()});
            }
            render::FrameStats stats = variants[v].renderer->render(time, view);  // waits for the GPU's timer results
            const double wall =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            stats.passes.insert(stats.passes.begin(), sampling.begin(), sampling.end());
            Row& row = rows[v];
            row.lights_drawn = stats.lights;
            row.atlas_triangles = stats.atlas_triangles;
            if (frame < o.warmup) continue;
            Samples& s = samples[v];
            s.frame_ms.push_back(wall);
            double total = 0.0;
            bool all_valid = true;
            for (const gl::PassTime& pass : stats.passes) {
                if (!s.pass_ms.count(pass.pass)) row.pass_order.push_back(pass.pass);
                std::vector<double>& times = s.pass_ms[pass.pass];
                // A GPU pass cannot outlast the frame that waited for it: llvmpipe times the first query
                // after the GPU sampler's transform feedback from 0 (it reads as the time since boot).
                if (pass.milliseconds > wall) {
                    all_valid = false;
                    continue;
                }
                times.push_back(pass.milliseconds);
                if (pass.pass != render::kFsSamplingPass) total += pass.milliseconds;  // GPU passes only
            }
            if (all_valid) s.gpu_ms.push_back(total);
        }
    }
    for (std::size_t v = 0; v < variants.size(); ++v) {
        rows[v].frame_ms = summarize(samples[v].frame_ms);
        rows[v].gpu_ms = summarize(samples[v].gpu_ms);
        rows[v].gpu_frames = samples[v].gpu_ms.size();
        for (auto& [pass, values] : samples[v].pass_ms)
            if (!values.empty()) rows[v].passes[pass] = summarize(values);  // else no valid reading: left out
        rows[v].ratio = rows[0].frame_ms.median > 0.0 ? rows[v].frame_ms.median / rows[0].frame_ms.median : 0.0;
    }
    return rows;
}

const char* pass_timing_name(gl::PassTiming timing) {
    return timing == gl::PassTiming::synchronous ? "wait" : "queries";
}

void print_table(const std::vector<Row>& rows, const BenchOptions& o, const std::string& renderer_name,
                 std::size_t triangles, gl::PassTiming timing, Hemisphere hemisphere) {
    std::printf(
        "envshadow bench  %s  |  %s (%s)  |  %zu triangles  |  %d frames after %d warm-up  |  passes timed by %s  |  "
        "lights of the %s\n",
        o.scene.c_str(), renderer_name.c_str(), o.backend.c_str(), triangles, o.frames, o.warmup,
        timing == gl::PassTiming::synchronous ? "waiting for each" : "GL_TIME_ELAPSED queries",
        hemisphere == Hemisphere::upper ? "upper hemisphere" : "full sphere");
    std::vector<std::string> pass_names;  // union over the rows, in pipeline order
    for (const Row& r : rows)
        for (std::size_t i = 0; i < r.pass_order.size(); ++i)
            if (std::find(pass_names.begin(), pass_names.end(), r.pass_order[i]) == pass_names.end())
                pass_names.insert(pass_names.begin() + std::ptrdiff_t(std::min(i, pass_names.size())), r.pass_order[i]);
    const bool variants = !o.variants.empty();
    std::printf("%-22s %5s %5s %5s %11s %17s %9s %9s", "setting", "N", "drawn", "tile", "resolution",
                "frame ms med/p95", "FPS med", "GPU ms");
    if (variants) std::printf(" %6s %10s", "ratio", "atlas tris");
    for (const std::string& pass : pass_names) std::printf(" %14s", (pass + " ms").c_str());
    if (variants) std::printf("  variant");
    std::printf("\n");
    for (const Row& r : rows) {
        const std::string resolution = std::to_string(r.width) + "x" + std::to_string(r.height);
        std::printf("%-22s %5d %5d %5d %11s %8.2f / %6.2f %9.1f", r.point.label.c_str(), r.lights, r.lights_drawn,
                    r.tile, resolution.c_str(), r.frame_ms.median, r.frame_ms.p95,
                    r.frame_ms.median > 0 ? 1000.0 / r.frame_ms.median : 0.0);
        if (r.gpu_frames > 0)
            std::printf(" %9.2f", r.gpu_ms.median);
        else
            std::printf(" %9s", "-");
        if (variants) std::printf(" %6.3f %10zu", r.ratio, r.atlas_triangles);
        for (const std::string& pass : pass_names) {
            auto it = r.passes.find(pass);
            if (it == r.passes.end())
                std::printf(" %14s", "-");  // not timed, or no valid reading
            else
                std::printf(" %14.2f", it->second.median);
        }
        if (variants) std::printf("  %s", r.variant.c_str());
        std::printf("\n");
    }
}

nlohmann::json to_json(const std::vector<Row>& rows, const BenchOptions& o, const std::string& renderer_name,
                       std::size_t triangles, gl::PassTiming timing) {
    auto summary = [](const TimeSummary& s) {
        return nlohmann::json{{"median", s.median}, {"p95", s.p95}, {"mean", s.mean}, {"min", s.min}, {"max", s.max}};
    };
    nlohmann::json out = {{"scene", o.scene},
                          {"renderer", renderer_name},
                          {"backend", o.backend},
                          {"method", o.method},
                          {"frames", o.frames},
                          {"warmup", o.warmup},
                          {"fs_importance", o.method == "fs-gpu" ? o.fs_importance : ""},
                          {"triangles", triangles},
                          {"atlas_mode", o.atlas},
                          {"variants", o.variants},
                          {"pass_timing", pass_timing_name(timing)},
                          {"rows", nlohmann::json::array()}};
    for (const Row& r : rows) {
        nlohmann::json passes = nlohmann::json::object();
        for (const auto& [pass, s] : r.passes) passes[pass] = summary(s);
        if (r.gpu_frames > 0) passes["total"] = summary(r.gpu_ms);
        out["rows"].push_back({{"setting", r.point.label},
                               {"variant", r.variant},
                               {"ratio_to_first_variant", r.ratio},
                               {"atlas_triangles", r.atlas_triangles},
                               {"lights", r.lights},
                               {"lights_drawn", r.lights_drawn},
                               {"tile", r.tile},
                               {"width", r.width},
                               {"height", r.height},
                               {"decompose_ms", r.decompose_ms},
                               {"frame_ms", summary(r.frame_ms)},
                               // FPS at the median frame time, and at the 95th-percentile (slow) frame time.
                               {"fps",
                                {{"median", r.frame_ms.median > 0 ? 1000.0 / r.frame_ms.median : 0.0},
                                 {"p95", r.frame_ms.p95 > 0 ? 1000.0 / r.frame_ms.p95 : 0.0}}},
                               {"gpu_ms", passes}});
    }
    return out;
}

// --fs-importance: "full" (0 x 0: the environment's own size) or W x H, within the map, W a multiple of 16
// (the sampler's unrolled scan).
glm::ivec2 fs_importance_size(const std::string& text, const EnvironmentMap& map) {
    if (text == "full") return {0, 0};
    int width = 0, height = 0;
    char x = 0, rest = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || x != 'x' || width < 16 ||
        height < 1 || width % 16 != 0 || width > map.width || height > map.height)
        throw UsageError("--fs-importance " + text +
                         ": give 'full' or WxH with W a multiple of 16, at most the map's " +
                         std::to_string(map.width) + "x" + std::to_string(map.height));
    return {width, height};
}

int run_bench(const BenchOptions& o) {
    // CLI::Range lets NaN through (every comparison with it is false).
    if (!std::isfinite(o.time_step)) throw UsageError("--time-step must be a finite number of seconds");
    const std::vector<SweepPoint> points =
        o.sweep.empty() ? std::vector<SweepPoint>{SweepPoint{0, 0, 0, 0, "default"}} : parse_sweep(o.sweep);
    for (const SweepPoint& p : points) {
        if (p.lights > kMaxLights)
            throw UsageError("--sweep " + p.label + ": N must be 1.." + std::to_string(kMaxLights));
        if (p.width > 16384 || p.height > 16384) throw UsageError("--sweep " + p.label + ": resolution too large");
    }
    render::RenderSettings settings;
    settings.depth_bits = o.depth_bits;
    settings.tile_size = o.tile;
    settings.atlas = render::parse_atlas_mode(o.atlas, "--atlas");
    settings = apply(o.optimisations, settings);
    render::validate(settings);
    // One renderer per variant (each with its own atlas), all in one context.
    std::vector<std::string> labels;
    for (std::size_t start = 0; start <= o.variants.size() && !o.variants.empty();) {
        const std::size_t semicolon = std::min(o.variants.find(';', start), o.variants.size());
        labels.push_back(o.variants.substr(start, semicolon - start));
        start = semicolon + 1;
    }
    if (labels.empty()) labels.push_back("");
    std::vector<Variant> variants;
    for (const std::string& label : labels)
        variants.push_back({label, render::apply_variant(settings, label, "--variants"), nullptr});

    Scene scene = load_scene(o.scene);
    if (!o.env.empty()) scene.environment.source = o.env;
    const EnvironmentMap map = load_environment(scene.environment.source);
    const glm::ivec2 importance_size = o.method == "fs-gpu" ? fs_importance_size(o.fs_importance, map) : glm::ivec2(0);

    auto context = gl::create_context(gl::parse_backend(o.backend));
    const std::string renderer_name = context->renderer();
    const gl::PassTiming timing = gl::parse_pass_timing(o.pass_timing, context->is_software(), "--pass-timing");
    for (Variant& variant : variants) {
        variant.renderer = std::make_unique<render::Renderer>(variant.settings);
        variant.renderer->set_pass_timing(timing);
        variant.renderer->set_scene(scene);
        variant.renderer->set_environment(map);
    }

    std::optional<render::FsSampler> sampler;
    if (o.method == "fs-gpu") {
        render::FsSamplerOptions options;
        options.importance_width = importance_size.x;
        options.importance_height = importance_size.y;
        sampler.emplace(render::embedded_shaders(), options);
    }

    std::map<int, Decomposition> decompositions;
    std::vector<Row> rows;
    for (const SweepPoint& point : points) {
        log::info("bench: " + point.label);
        for (Row& row : measure(o, point, scene, map, variants, decompositions, sampler ? &*sampler : nullptr))
            rows.push_back(std::move(row));
    }
    print_table(rows, o, renderer_name, scene.triangle_count(), timing, visible_hemisphere(scene));
    if (!o.json.empty())
        write_file_atomically(o.json, to_json(rows, o, renderer_name, scene.triangle_count(), timing).dump(2) + "\n");
    return 0;
}

}  // namespace

Command add_bench_command(CLI::App& parent) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* app = parent.add_subcommand("bench", "Measure frame times headless (GPU timer queries per pass)");
    app->add_option("--scene", o->scene, "Scene JSON or .gltf/.glb")->required();
    app->add_option("--env", o->env, "Environment (.exr, .hdr, builtin:…), overrides the scene's");
    app->add_option("--lights", o->lights, "Number of cells N")->check(CLI::Range(1, kMaxLights));
    app->add_option(
           "--method", o->method,
           "Decomposition: lloyd, ccvt, mediancut, random, fs; or fs-gpu (lights sampled on the GPU every frame)")
        ->check(CLI::IsMember({"lloyd", "ccvt", "mediancut", "random", "fs", "fs-gpu"}));
    app->add_option("--fs-importance", o->fs_importance, "fs-gpu: importance map size, WxH or full (default 256x128)");
    app->add_option("--seed", o->seed, "Seed of the decomposition");
    app->add_option("--frames", o->frames, "Timed frames")->check(CLI::Range(1, 100000));
    app->add_option("--warmup", o->warmup, "Untimed frames first")->check(CLI::Range(0, 100000));
    app->add_option("--width", o->width, "Image width")->check(CLI::Range(16, 16384));
    app->add_option("--height", o->height, "Image height")->check(CLI::Range(16, 16384));
    app->add_option("--tile", o->tile, "Shadow tile resolution")->check(CLI::Range(128, 2048));
    app->add_option("--depth-bits", o->depth_bits, "Shadow depth format")->check(CLI::IsMember({16, 32}));
    app->add_option("--atlas", o->atlas, "clip-distances (one draw), viewport-array, per-tile (baseline)");
    app->add_option("--time-step", o->time_step, "Animation seconds per frame")->check(CLI::Range(0.0, 10.0));
    app->add_option("--backend", o->backend, "egl or osmesa")->check(CLI::IsMember({"egl", "osmesa"}));
    add_pass_timing_option(app, &o->pass_timing);
    app->add_option("--json", o->json, "Write the results as JSON");
    app->add_option(
        "--variants", o->variants,
        "Interleaved variants, ';'-separated: baseline, optimised, or key=value,… (caster-lod, prepass, ubo, "
        "cull, specialise, tiles, flat, depth-bits, tile, atlas, pcf); ratios to the first");
    add_optimisation_options(app, &o->optimisations);
    app->add_option("--sweep", o->sweep, "One row per setting: lights=16,32,…  resolution=640x360,…  tile=128,…");
    return {app, [o] { return run_bench(*o); }};
}

}  // namespace envshadow::app
