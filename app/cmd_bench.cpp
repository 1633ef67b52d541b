// `envshadow bench`: frame times of a scene, headless. Warm-up frames, then F timed frames with the
// animation running (the shadow atlas really is redrawn every frame); per-pass GPU times from timer
// queries and the wall time of each frame; medians and 95th percentiles. `--sweep` repeats the run
// for each setting, so the growth of the cost with N (or resolution, or tile size) can be read off.
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
    std::string scene, env, method = "lloyd", backend = "egl", json, sweep, atlas = "clip-distances";
    int lights = 128, frames = 100, warmup = 10, width = 1280, height = 720, tile = 256, depth_bits = 16;
    double time_step = 1.0 / 60.0;  // animation seconds per frame
    std::uint64_t seed = 1;
};

struct Row {
    SweepPoint point;
    int lights = 0, lights_drawn = 0, tile = 0, width = 0, height = 0;
    double decompose_ms = 0.0;
    TimeSummary frame_ms;                     // wall time per frame, CPU and GPU
    std::vector<std::string> pass_order;        // as the renderer reports them (pipeline order)
    std::map<std::string, TimeSummary> passes;  // GPU time per pass
    TimeSummary gpu_ms;                       // sum of the passes per frame
};

Row measure(const BenchOptions& o, const SweepPoint& point, const Scene& scene, const EnvironmentMap& map,
            render::Renderer& renderer, std::map<int, Decomposition>& decompositions) {
    Row row;
    row.point = point;
    row.lights = point.lights ? point.lights : o.lights;
    row.tile = point.tile ? point.tile : o.tile;
    row.width = point.width ? point.width : o.width;
    row.height = point.height ? point.height : o.height;

    auto found = decompositions.find(row.lights);
    if (found == decompositions.end())
        found = decompositions.emplace(row.lights, decompose(map, DecomposeOptions{parse_method(o.method), row.lights, o.seed})).first;
    row.decompose_ms = found->second.seconds * 1000.0;

    render::RenderSettings settings = renderer.settings();
    settings.tile_size = row.tile;
    renderer.set_settings(settings);
    renderer.set_lights(found->second.cells);

    std::vector<double> frame_ms, gpu_ms;
    std::map<std::string, std::vector<double>> pass_ms;
    double time = 0.0;
    for (int frame = 0; frame < o.warmup + o.frames; ++frame, time += o.time_step) {
        const render::CameraView view = render::camera_view(scene, row.width, row.height, time);
        const auto start = std::chrono::steady_clock::now();
        const render::FrameStats stats = renderer.render(time, view);  // waits for the GPU's timer results
        const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        row.lights_drawn = stats.lights;
        if (frame < o.warmup) continue;
        frame_ms.push_back(wall);
        double total = 0.0;
        for (const gl::PassTime& pass : stats.passes) {
            if (!pass_ms.count(pass.pass)) row.pass_order.push_back(pass.pass);
            pass_ms[pass.pass].push_back(pass.milliseconds);
            total += pass.milliseconds;
        }
        gpu_ms.push_back(total);
    }
    row.frame_ms = summarize(frame_ms);
    row.gpu_ms = summarize(gpu_ms);
    for (auto& [pass, values] : pass_ms) row.passes[pass] = summarize(values);
    return row;
}

void print_table(const std::vector<Row>& rows, const BenchOptions& o, const std::string& renderer_name,
                 std::size_t triangles) {
    std::printf("envshadow bench  %s  |  %s (%s)  |  %zu triangles  |  %d frames after %d warm-up\n", o.scene.c_str(),
                renderer_name.c_str(), o.backend.c_str(), triangles, o.frames, o.warmup);
    const std::vector<std::string>& pass_names = rows.front().pass_order;
    std::printf("%-22s %5s %5s %5s %11s %17s %9s %9s", "setting", "N", "drawn", "tile", "resolution",
                "frame ms med/p95", "FPS med", "GPU ms");
    for (const std::string& pass : pass_names) std::printf(" %14s", (pass + " ms").c_str());
    std::printf("\n");
    for (const Row& r : rows) {
        const std::string resolution = std::to_string(r.width) + "x" + std::to_string(r.height);
        std::printf("%-22s %5d %5d %5d %11s %8.2f / %6.2f %9.1f %9.2f", r.point.label.c_str(), r.lights, r.lights_drawn,
                    r.tile, resolution.c_str(), r.frame_ms.median, r.frame_ms.p95,
                    r.frame_ms.median > 0 ? 1000.0 / r.frame_ms.median : 0.0, r.gpu_ms.median);
        for (const std::string& pass : pass_names) {
            auto it = r.passes.find(pass);
            std::printf(" %14.2f", it == r.passes.end() ? 0.0 : it->second.median);
        }
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
                          {"triangles", triangles},  {"atlas_mode", o.atlas},     {"rows", nlohmann::json::array()}};
    for (const Row& r : rows) {
        nlohmann::json passes = nlohmann::json::object();
        for (const auto& [pass, s] : r.passes) passes[pass] = summary(s);
        passes["total"] = summary(r.gpu_ms);
        out["rows"].push_back({{"setting", r.point.label},
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
    render::validate(settings);

    Scene scene = load_scene(o.scene);
    if (!o.env.empty()) scene.environment.source = o.env;
    const EnvironmentMap map = load_environment(scene.environment.source);

    auto context = gl::create_context(gl::parse_backend(o.backend));
    const std::string renderer_name = context->renderer();
    render::Renderer renderer(settings);
    renderer.set_scene(scene);
    renderer.set_environment(map);

    std::map<int, Decomposition> decompositions;
    std::vector<Row> rows;
    for (const SweepPoint& point : points) {
        log::info("bench: " + point.label);
        rows.push_back(measure(o, point, scene, map, renderer, decompositions));
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
    app->add_option("--sweep", o->sweep, "One row per setting: lights=16,32,…  resolution=640x360,…  tile=128,…");
    return {app, [o] { return run_bench(*o); }};
}

}  // namespace envshadow::app
