// `envshadow bench`: frame times of a scene, headless. Warm-up frames, then F timed frames with the
// animation running (the moving casters' shadows really are redrawn every frame); per-pass GPU times from timer
// queries and the wall time of each frame; medians and 95th percentiles. `--sweep` repeats the run
// for each setting, so the growth of the cost with N (or resolution, or tile size) can be read off.
// `--variants "baseline;optimised;…"` renders every timed frame once per variant (one renderer
// each, interleaved frame by frame), so their ratios are measured under the same machine load.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench_stats.h"
#include "commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/image.h"
#include "core/log.h"
#include "env/cells.h"
#include "env/environment.h"
#include "gl/context.h"
#include "inputs.h"
#include "render/light_source.h"
#include "render/renderer.h"
#include "session.h"
#include "variants.h"

namespace envshadow::app {
namespace {

struct BenchOptions {
    CommonOptions common;  // --scene, --env, --lights, --method, --seed, --width, --height, --backend, --fs-importance
    SettingOptions settings;  // --tile, --atlas, --shading, ... (render::setting_table()), --baseline
    std::string json, sweep, variants, pass_timing = "auto";
    int frames = 100, warmup = 10;
    double time_step = 1.0 / 60.0;  // animation seconds per frame
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

struct RendererVariant {
    Variant variant;
    std::unique_ptr<RenderSession> session;
};

// One row per variant for this sweep point; the variants' frames are interleaved.
// A per-frame light source samples the GPU before every frame; the sampling is part of the frame's
// wall time and reported as its own column (wall time, up to the lights' read-back).
std::vector<Row> measure(const BenchOptions& o, const SweepPoint& point, const Scene& scene,
                         std::vector<RendererVariant>& variants, render::LightSource& lights) {
    Row common;
    common.point = point;
    common.lights = point.lights ? point.lights : o.common.lights;
    common.width = point.width ? point.width : o.common.width;
    common.height = point.height ? point.height : o.common.height;
    common.decompose_ms = lights.decomposition().seconds * 1000.0;

    std::vector<Row> rows(variants.size(), common);
    struct Samples {
        std::vector<double> frame_ms, gpu_ms;
        std::map<std::string, std::vector<double>> pass_ms;
    };
    std::vector<Samples> samples(variants.size());
    for (std::size_t v = 0; v < variants.size(); ++v) {
        render::RenderSettings settings = variants[v].variant.settings;
        if (point.tile) settings.tile_size = point.tile;
        variants[v].session->set_settings(settings);
        lights.attach(variants[v].session->renderer());
        rows[v].variant = variants[v].variant.label;
        rows[v].tile = settings.tile_size;
    }
    double time = 0.0;
    for (int frame = 0; frame < o.warmup + o.frames; ++frame, time += o.time_step) {
        const render::CameraView view = render::camera_view(scene, common.width, common.height, time);
        for (std::size_t v = 0; v < variants.size(); ++v) {
            const auto start = std::chrono::steady_clock::now();
            // Waits for the sampler (per frame), then for the GPU's timer results.
            render::FrameStats stats = variants[v].session->render(lights, time, view);
            // Wall time: GL_TIME_ELAPSED around the sampler's compute and transform feedback is unreliable
            // on llvmpipe and spoils the renderer's next query (docs/PERFORMANCE.md).
            std::vector<gl::PassTime> sampling;
            if (lights.per_frame()) sampling.push_back({render::kFsSamplingPass, lights.sampling_ms()});
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

void print_table(const std::vector<Row>& rows, const BenchOptions& o, const render::RenderSettings& settings,
                 const std::string& renderer_name, std::size_t triangles, gl::PassTiming timing,
                 Hemisphere hemisphere) {
    std::printf(
        "envshadow bench  %s  |  %s (%s)  |  %zu triangles  |  %d frames after %d warm-up  |  passes timed by %s  |  "
        "lights from the %s  |  shading %s  |  shadows %s\n",
        o.common.scene.c_str(), renderer_name.c_str(), o.common.backend.c_str(), triangles, o.frames, o.warmup,
        timing == gl::PassTiming::synchronous ? "waiting for each" : "GL_TIME_ELAPSED queries",
        hemisphere_words(hemisphere), std::string(to_string(settings.shading)).c_str(),
        std::string(to_string(settings.shadows)).c_str());
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

nlohmann::json to_json(const std::vector<Row>& rows, const BenchOptions& o, const render::RenderSettings& settings,
                       const std::string& renderer_name, std::size_t triangles, gl::PassTiming timing) {
    auto summary = [](const TimeSummary& s) {
        return nlohmann::json{{"median", s.median}, {"p95", s.p95}, {"mean", s.mean}, {"min", s.min}, {"max", s.max}};
    };
    const bool gpu_sampler = render::light_method(o.common.method).kind == render::LightSourceKind::gpu_fs;
    nlohmann::json out = {{"scene", o.common.scene},
                          {"renderer", renderer_name},
                          {"backend", o.common.backend},
                          {"method", o.common.method},
                          {"frames", o.frames},
                          {"warmup", o.warmup},
                          {"fs_importance", gpu_sampler ? o.common.fs_importance : ""},
                          {"triangles", triangles},
                          {"atlas_mode", to_string(settings.atlas)},
                          {"variants", o.variants},
                          {"pass_timing", std::string(to_string(timing))},
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

int run_bench(const BenchOptions& o) {
    const CommonOptions& c = o.common;
    const std::vector<SweepPoint> points =
        o.sweep.empty() ? std::vector<SweepPoint>{SweepPoint{0, 0, 0, 0, "default"}} : parse_sweep(o.sweep);
    for (const SweepPoint& p : points) {
        if (p.lights > kMaxLights)
            throw UsageError("--sweep " + p.label + ": N must be 1.." + std::to_string(kMaxLights));
        if (p.width > kMaxImageWidth || p.height > kMaxImageHeight)
            throw UsageError("--sweep " + p.label + ": resolution too large");
    }
    // As render and view: bench measures what a user sees.
    const render::RenderSettings settings = settings_from(o.settings, command_defaults());
    // One renderer per variant (each with its own atlas), all in one context.
    std::vector<RendererVariant> variants;
    for (Variant& variant : parse_variants(o.variants, settings)) variants.push_back({std::move(variant), nullptr});

    const Inputs inputs = load_inputs(c.scene, c.env, 0.0);
    const Scene& scene = inputs.scene;
    const EnvironmentMap& map = inputs.map;
    const render::LightMethod& method = render::light_method(c.method);
    const Hemisphere hemisphere = hemisphere_for(c.hemisphere, scene);
    const render::FsSamplerOptions fs_options = method.kind == render::LightSourceKind::gpu_fs
                                                    ? fs_sampler_options(c.fs_importance, map)
                                                    : render::FsSamplerOptions{};

    auto context = gl::create_context(gl::parse_backend(c.backend));
    const std::string renderer_name = context->renderer();
    const gl::PassTiming timing = pass_timing(o.pass_timing, context->is_software());
    for (RendererVariant& variant : variants)
        variant.session = std::make_unique<RenderSession>(inputs, variant.variant.settings, timing, Report::quiet);

    // The lights of each N of the sweep, made once.
    std::map<int, render::LightSource> light_sources;
    std::vector<Row> rows;
    for (const SweepPoint& point : points) {
        log::info("bench: " + point.label);
        const int lights = point.lights ? point.lights : c.lights;
        auto found = light_sources.find(lights);
        if (found == light_sources.end())
            found = light_sources
                        .emplace(lights, render::make_light_source(method, map, lights, c.seed, hemisphere, fs_options))
                        .first;
        for (Row& row : measure(o, point, scene, variants, found->second)) rows.push_back(std::move(row));
    }
    print_table(rows, o, settings, renderer_name, scene.triangle_count(), timing, hemisphere);
    if (!o.json.empty())
        write_file_atomically(o.json,
                              to_json(rows, o, settings, renderer_name, scene.triangle_count(), timing).dump(2) + "\n");
    return 0;
}

}  // namespace

Command add_bench_command(CLI::App& parent) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* app = parent.add_subcommand("bench", "Measure frame times headless (GPU timer queries per pass)");
    o->common.width = 1280;
    o->common.height = 720;
    add_common_options(app, &o->common, CommonOptionSet{});
    app->add_option("--frames", o->frames, "Timed frames")->check(CLI::Range(1, 100000));
    app->add_option("--warmup", o->warmup, "Untimed frames first")->check(CLI::Range(0, 100000));
    add_setting_options(app, &o->settings, command_defaults());
    app->add_option("--time-step", o->time_step, "Animation seconds per frame")
        ->check(CLI::Range(0.0, 10.0))
        ->check(finite_number());
    add_pass_timing_option(app, &o->pass_timing);
    app->add_option("--json", o->json, "Write the results as JSON");
    app->add_option("--variants", o->variants,
                    "Interleaved variants, ';'-separated: baseline, optimised, or key=value,… with the keys " +
                        variant_keys() + "; ratios to the first");
    app->add_option("--sweep", o->sweep, "One row per setting: lights=16,32,…  resolution=640x360,…  tile=128,…");
    return {app, [o] { return run_bench(*o); }};
}

}  // namespace envshadow::app
