// Times each decomposition method on a 1024 x 512 photograph (city; lloyd and ccvt on studio too) at
// N = 64 and 128, and the nearest-site search against the brute force it replaces, in one run:
//   build/tests/bench/bench_decompose [--benchmark_repetitions=5 --benchmark_report_aggregates_only=true]
#include <benchmark/benchmark.h>

#include <string>

#include "env/cells.h"
#include "env/environment.h"
#include "env/importance.h"
#include "env/nearest_site.h"

namespace envshadow {
namespace {

const char* const kWorld = "/usr/share/blender/datafiles/studiolights/world/";

const EnvironmentMap& city() {
    static const EnvironmentMap map = load_environment(std::string(kWorld) + "city.exr");
    return map;
}
// Softboxes on black: where CCVT's capacity solve is hardest.
const EnvironmentMap& studio() {
    static const EnvironmentMap map = load_environment(std::string(kWorld) + "studio.exr");
    return map;
}

void decompose_with(benchmark::State& state, Method method, SiteSearch search, const EnvironmentMap& map = city()) {
    DecomposeOptions options;
    options.method = method;
    options.lights = int(state.range(0));
    options.search = search;
    Decomposition d;
    for (auto _ : state) {
        d = decompose(map, options);
        benchmark::DoNotOptimize(d.cells.data());
    }
    state.counters["iterations"] = d.iterations;
    state.counters["coarse_iterations"] = d.coarse_iterations;
    state.counters["final_movement"] = d.final_movement;
    state.counters["cells"] = double(d.cells.size());
}

void BM_decompose(benchmark::State& state, Method method) {
    decompose_with(state, method, SiteSearch::tiles);
}
void BM_decompose_studio(benchmark::State& state, Method method) {
    decompose_with(state, method, SiteSearch::tiles, studio());
}
// Lloyd with every texel scored against every site at every iteration: the baseline.
void BM_decompose_lloyd_brute_force(benchmark::State& state) {
    decompose_with(state, Method::lloyd, SiteSearch::brute_force);
}

// One nearest-site assignment of the whole map, with the sites of a converged Lloyd decomposition.
std::vector<glm::dvec3> lloyd_sites(int lights) {
    DecomposeOptions options;
    options.lights = lights;
    return decompose(city(), options).sites;
}

void BM_assign_tiles(benchmark::State& state) {
    const ImportanceMap importance = build_importance(city());
    const NearestSiteSearch search(importance);
    const std::vector<glm::dvec3> sites = lloyd_sites(int(state.range(0)));
    std::vector<std::uint16_t> texel_cell(importance.texel_count());
    for (auto _ : state) {
        search.assign(sites, {}, texel_cell);
        benchmark::DoNotOptimize(texel_cell.data());
    }
}

void BM_assign_brute_force(benchmark::State& state) {
    const ImportanceMap importance = build_importance(city());
    const std::vector<glm::dvec3> sites = lloyd_sites(int(state.range(0)));
    std::vector<std::uint16_t> texel_cell(importance.texel_count());
    for (auto _ : state) {
        assign_nearest_brute_force(importance, sites, {}, texel_cell);
        benchmark::DoNotOptimize(texel_cell.data());
    }
}

// N = 64 and 128, wall-clock milliseconds (the work runs on both cores).
void light_counts(benchmark::internal::Benchmark* b) {
    b->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK_CAPTURE(BM_decompose, lloyd, Method::lloyd)->Apply(light_counts);
BENCHMARK_CAPTURE(BM_decompose, ccvt, Method::ccvt)->Apply(light_counts);
BENCHMARK_CAPTURE(BM_decompose, mediancut, Method::mediancut)->Apply(light_counts);
BENCHMARK_CAPTURE(BM_decompose, random, Method::random)->Apply(light_counts);
BENCHMARK_CAPTURE(BM_decompose, fs, Method::fs)->Apply(light_counts);
BENCHMARK_CAPTURE(BM_decompose_studio, lloyd, Method::lloyd)->Apply(light_counts);
BENCHMARK_CAPTURE(BM_decompose_studio, ccvt, Method::ccvt)->Apply(light_counts);
BENCHMARK(BM_decompose_lloyd_brute_force)->Apply(light_counts)->Iterations(1);
BENCHMARK(BM_assign_tiles)->Apply(light_counts);
BENCHMARK(BM_assign_brute_force)->Apply(light_counts);

}  // namespace
}  // namespace envshadow

BENCHMARK_MAIN();
