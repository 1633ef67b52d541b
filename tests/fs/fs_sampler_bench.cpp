// GPU time of the Floyd-Steinberg sampler per frame (its three passes), measured with a pair of
// GL_TIMESTAMP queries around FsSampler::sample, on city.exr (1024 x 512) at importance maps of
// 256 x 128 and 1024 x 512; Szirmay-Kalos et al. §1.3.2 report 47 ms for 1024 x 512 on a GeForce 8800. Each
// benchmark runs 25 frames after 3 warm-up ones and reports the median as gpu_ms_median, and the
// median wall-clock time between two glFinish calls as wall_ms_median.
// Timestamps, not GL_TIME_ELAPSED: Mesa 22.3's llvmpipe returns 0 for compute dispatches and garbage
// (10^6 ms) for the transform feedback draw under TIME_ELAPSED. Its timestamps are right for these
// passes, which it runs synchronously (wall_ms_median checks them), though not for rasterised draws.
//   build/tests/fs/bench_fs_sampler [--benchmark_filter=...]   (ENVSHADOW_FS_BACKEND=osmesa for OSMesa)
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "fs_reference.h"
#include "gl/context.h"
#include "render/embedded_shaders.h"
#include "render/fs_sampler.h"

namespace envshadow::testing {
namespace {

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

struct Setup {
    std::unique_ptr<gl::Context> context;
    gl::ShaderLibrary shaders;
    gl::Texture city;
};

Setup& setup() {
    static Setup s = [] {
        Setup made;
        const char* backend = std::getenv("ENVSHADOW_FS_BACKEND");
        made.context = gl::create_context(gl::parse_backend(backend ? backend : "egl"), gl::ContextOptions{64, 64});
        made.shaders = render::embedded_shaders();
        made.city = upload(city_map());
        return made;
    }();
    return s;
}

// Arguments: importance width (0: the CPU method's blocks, FsWeighting::adaptive_blocks), M,
// double-precision scan (1/0).
void BM_FsSampler(benchmark::State& state) {
    Setup& s = setup();
    const int width = int(state.range(0)), samples = int(state.range(1));
    render::FsSamplerOptions options{width, width / 2};
    options.double_precision_scan = state.range(2) != 0;
    if (width == 0) options.weighting = render::FsWeighting::adaptive_blocks;
    render::FsSampler sampler(s.shaders, options);
    for (int warm_up = 0; warm_up < 3; ++warm_up) sampler.sample(s.city, render::FsSampleRequest{samples});
    const gl::Query begin = gl::Query::create(GL_TIMESTAMP), end = gl::Query::create(GL_TIMESTAMP);
    std::vector<double> totals, walls;
    for (auto _ : state) {
        glFinish();
        const auto wall_begin = std::chrono::steady_clock::now();
        glQueryCounter(begin.id(), GL_TIMESTAMP);
        sampler.sample(s.city, render::FsSampleRequest{samples});
        glQueryCounter(end.id(), GL_TIMESTAMP);
        glFinish();
        const std::chrono::duration<double, std::milli> wall = std::chrono::steady_clock::now() - wall_begin;
        walls.push_back(wall.count());
        GLuint64 begin_ns = 0, end_ns = 0;
        glGetQueryObjectui64v(begin.id(), GL_QUERY_RESULT, &begin_ns);
        glGetQueryObjectui64v(end.id(), GL_QUERY_RESULT, &end_ns);
        totals.push_back(double(end_ns - begin_ns) * 1e-6);
        state.SetIterationTime(totals.back() * 1e-3);
    }
    state.counters["gpu_ms_median"] = median(totals);
    state.counters["wall_ms_median"] = median(walls);
    state.counters["lights"] = double(sampler.read_counts().light_count);
    state.counters["importance_width"] = double(sampler.importance_size().x);
    state.SetLabel(s.context->renderer());
}

BENCHMARK(BM_FsSampler)
    ->ArgNames({"width", "M", "double"})
    ->Args({256, 128, 1})
    ->Args({1024, 128, 1})
    ->Args({256, 128, 0})
    ->Args({1024, 128, 0})
    ->Args({256, 64, 1})
    ->Args({1024, 256, 1})
    ->Args({0, 128, 1})
    ->UseManualTime()
    ->Iterations(25)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace envshadow::testing

BENCHMARK_MAIN();
