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
#include "render/renderer.h"
#include "scene/scene.h"

namespace envshadow::app {
namespace {

struct BenchOptions {
    std::string scene, env, method = "lloyd", backend = "egl", json, sweep, atlas = "clip-distances", variants,
        caster_lod, prepass;
    bool baseline = false;
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
    TimeSummary frame_ms;                     // wall time per frame, CPU and GPU
    std::vector<std::string> pass_order;        // as the renderer reports them (pipeline order)
    std::map<std::string, TimeSummary> passes;  // GPU time per pass
    TimeSummary gpu_ms;                       // sum of the passes per frame
};

struct Variant {
    std::string label;
    render::RenderSettings settings;
    std::unique_ptr<render::Renderer> renderer;
};

// One row per variant for this sweep point; the variants' frames are interleaved.
std::vector<Row> measure(const BenchOptions& o, const SweepPoint& point, const Scene& scene, const EnvironmentMap& map,
                         std::vector<Variant>& variants, std::map<int, Decomposition>& decompositions) {
    Row common;
    common.point = point;
    common.lights = point.lights ? point.lights : o.lights;
    common.width = point.width ? point.width : o.width;
    common.height = point.height ? point.height : o.height;

    auto found = decompositions.find(common.lights);
    if (found == decompositions.end())
        found = decompositions.emplace(common.lights, decompose(map, DecomposeOptions{parse_method(o.method), common.lights, o.seed})).first;
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
            const render::FrameStats stats = variants[v].renderer->render(time, view);  // waits for the GPU's timer results
            const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            Row& row = rows[v];
            row.lights_drawn = stats.lights;
            row.atlas_triangles = stats.atlas_triangles;
            if (frame < o.warmup) continue;
            Samples& s = samples[v];
            s.frame_ms.push_back(wall);
            double total = 0.0;
            for (const gl::PassTime& pass : stats.passes) {
                if (!s.pass_ms.count(pass.pass)) row.pass_order.push_back(pass.pass);
                s.pass_ms[pass.pass].push_back(pass.milliseconds);
                total += pass.milliseconds;
            }
            s.gpu_ms.push_back(total);
        }
    }
    for (std::size_t v = 0; v < variants.size(); ++v) {
        rows[v].frame_ms = summarize(samples[v].frame_ms);
        rows[v].gpu_ms = summarize(samples[v].gpu_ms);
        for (auto& [pass, values] : samples[v].pass_ms) rows[v].passes[pass] = summarize(values);
        rows[v].ratio = rows[0].frame_ms.median > 0.0 ? rows[v].frame_ms.median / rows[0].frame_ms.median : 0.0;
    }
    return rows;
}

void print_table(const std::vector<Row>& rows, const BenchOptions& o, const std::string& renderer_name,
                 std::size_t triangles) {
    std::printf("envshadow bench  %s  |  %s (%s)  |  %zu triangles  |  %d frames after %d warm-up\n", o.scene.c_str(),
                renderer_name.c_str(), o.backend.c_str(), triangles, o.frames, o.warmup);
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
        std::printf("%-22s %5d %5d %5d %11s %8.2f / %6.2f %9.1f %9.2f", r.point.label.c_str(), r.lights, r.lights_drawn,
                    r.tile, resolution.c_str(), r.frame_ms.median, r.frame_ms.p95,
                    r.frame_ms.median > 0 ? 1000.0 / r.frame_ms.median : 0.0, r.gpu_ms.median);
        if (variants) std::printf(" %6.3f %10zu", r.ratio, r.atlas_triangles);
        for (const std::string& pass : pass_names) {
            auto it = r.passes.find(pass);
            std::printf(" %14.2f", it == r.passes.end() ? 0.0 : it->second.median);
        }
        if (variants) std::printf("  %s", r.variant.c_str());
        std::printf("\n");
    }
}

nlohmann::json to_json(const std::vector<Row>& rows, const BenchOptions& o, const std::string& renderer_name,
                       std::size_t triangles) {
    auto summary = [](const TimeSummary& s) {
        return nlohmann::json{{"median", s.median}, {"p95", s.p95}, {"mean", s.mean}, {"min", s.min}, {"max", s.max}};
    };
    nlohmann::json out = {{"scene", o.scene},        {"renderer", renderer_name}, {"backend", o.backend},
                          {"method", o.method},      {"frames", o.frames},        {"warmup", o.warmup},
                          {"triangles", triangles},  {"atlas_mode", o.atlas},     {"variants", o.variants},
                          {"rows", nlohmann::json::array()}};
    for (const Row& r : rows) {
        nlohmann::json passes = nlohmann::json::object();
        for (const auto& [pass, s] : r.passes) passes[pass] = summary(s);
        passes["total"] = summary(r.gpu_ms);
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
                               {"fps", {{"median", r.frame_ms.median > 0 ? 1000.0 / r.frame_ms.median : 0.0},
                                        {"p95", r.frame_ms.p95 > 0 ? 1000.0 / r.frame_ms.p95 : 0.0}}},
                               {"gpu_ms", passes}});
    }
    return out;
}

int run_bench(const BenchOptions& o) {
    // CLI::Range lets NaN through (every comparison with it is false).
    if (!std::isfinite(o.time_step)) throw UsageError("--time-step must be a finite number of seconds");
    const std::vector<SweepPoint> points = o.sweep.empty() ? std::vector<SweepPoint>{SweepPoint{0, 0, 0, 0, "default"}}
                                                           : parse_sweep(o.sweep);
    for (const SweepPoint& p : points) {
        if (p.lights > kMaxLights) throw UsageError("--sweep " + p.label + ": N must be 1.." + std::to_string(kMaxLights));
        if (p.width > 16384 || p.height > 16384) throw UsageError("--sweep " + p.label + ": resolution too large");
    }
    render::RenderSettings settings;
    settings.depth_bits = o.depth_bits;
    settings.tile_size = o.tile;
    settings.atlas = render::parse_atlas_mode(o.atlas, "--atlas");
    if (o.baseline) settings = render::baseline(settings);
    if (!o.caster_lod.empty()) settings = render::apply_variant(settings, "caster-lod=" + o.caster_lod, "--caster-lod");
    if (!o.prepass.empty()) settings = render::apply_variant(settings, "prepass=" + o.prepass, "--prepass");
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

    auto context = gl::create_context(gl::parse_backend(o.backend));
    const std::string renderer_name = context->renderer();
    for (Variant& variant : variants) {
        variant.renderer = std::make_unique<render::Renderer>(variant.settings);
        variant.renderer->set_scene(scene);
        variant.renderer->set_environment(map);
    }

    std::map<int, Decomposition> decompositions;
    std::vector<Row> rows;
    for (const SweepPoint& point : points) {
        log::info("bench: " + point.label);
        for (Row& row : measure(o, point, scene, map, variants, decompositions)) rows.push_back(std::move(row));
    }
    print_table(rows, o, renderer_name, scene.triangle_count());
    if (!o.json.empty()) write_file_atomically(o.json, to_json(rows, o, renderer_name, scene.triangle_count()).dump(2) + "\n");
    return 0;
}

}  // namespace

Command add_bench_command(CLI::App& parent) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* app = parent.add_subcommand("bench", "Measure frame times headless (GPU timer queries per pass)");
    app->add_option("--scene", o->scene, "Scene JSON or .gltf/.glb")->required();
    app->add_option("--env", o->env, "Environment (.exr, .hdr, builtin:…), overrides the scene's");
    app->add_option("--lights", o->lights, "Number of cells N")->check(CLI::Range(1, kMaxLights));
    app->add_option("--method", o->method, "Decomposition method")
        ->check(CLI::IsMember({"lloyd", "ccvt", "mediancut", "random", "fs"}));
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
    app->add_option("--json", o->json, "Write the results as JSON");
    app->add_option("--variants", o->variants,
                    "Interleaved variants, ';'-separated: baseline, optimised, or key=value,… (caster-lod, prepass, "
                    "depth-bits, tile, atlas, pcf); ratios to the first");
    app->add_flag("--baseline", o->baseline, "The first working renderer: every issue-10 optimisation off");
    app->add_option("--caster-lod", o->caster_lod, "Caster LOD error in shadow texels, or off")->type_name("F|off");
    app->add_option("--prepass", o->prepass, "Depth pre-pass before shading: on or off")->check(CLI::IsMember({"on", "off"}));
    app->add_option("--sweep", o->sweep, "One row per setting: lights=16,32,…  resolution=640x360,…  tile=128,…");
    return {app, [o] { return run_bench(*o); }};
}

}  // namespace envshadow::app
