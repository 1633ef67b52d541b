// Times each decomposition method on a 1024 x 512 photograph (city; lloyd and ccvt on studio too) at
// N = 64 and 128, and the nearest-site search against the brute force it replaces, in one run:
//   build/tests/bench/bench_decompose [--benchmark_repetitions=5 --benchmark_report_aggregates_only=true]
// BM_cli_cold/MAP/HEMISPHERE is what `envshadow decompose` (full) and `render` on a scene with a ground
// (upper) print: lloyd at the CLI's defaults, the first decompose() of a new process (this binary run
// again with --cold), after the map's loading, with the CLI's malloc settings; BM_cli_warm the same
// call repeated in one process.
#include <benchmark/benchmark.h>
#include <malloc.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <stdexcept>
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

const std::array<const char*, 8> kMaps = {"city",  "courtyard", "forest",  "interior",
                                          "night", "studio",    "sunrise", "sunset"};

// What the CLI decomposes at load time: its DecomposeOptions defaults (lloyd, N = 128, seed 1).
DecomposeOptions cli_options(Hemisphere hemisphere) {
    DecomposeOptions options;
    options.hemisphere = hemisphere;
    return options;
}

// The malloc settings of app/main.cpp, which the printed time depends on (freed pages kept mapped).
void use_cli_malloc_settings() {
#if defined(__GLIBC__)
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
#endif
}

// bench_decompose --cold MAP HEMISPHERE: loads the map, decomposes it once and prints the seconds
// Decomposition::seconds holds, the interval the CLI prints.
int run_cold(const char* map_name, const char* hemisphere) {
    use_cli_malloc_settings();
    const EnvironmentMap map = load_environment(std::string(kWorld) + map_name + ".exr");
    std::printf("%.9f\n", decompose(map, cli_options(parse_enum<Hemisphere>(hemisphere))).seconds);
    return 0;
}

// One cold run in a new process of this binary; its printed seconds.
double cold_seconds(const char* map_name, const char* hemisphere) {
    int out[2];
    if (pipe(out) != 0) throw std::runtime_error("pipe failed");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, out[0]);
    std::string exe = "/proc/self/exe", flag = "--cold", map = map_name, half = hemisphere;
    char* argv[] = {exe.data(), flag.data(), map.data(), half.data(), nullptr};
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, exe.c_str(), &actions, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    close(out[1]);
    std::string text;
    char buffer[64];
    for (ssize_t n; (n = read(out[0], buffer, sizeof buffer)) > 0;) text.append(buffer, size_t(n));
    close(out[0]);
    int status = 0;
    if (spawned != 0 || waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0 ||
        text.empty())
        throw std::runtime_error("the cold run of " + map + " failed");
    return std::stod(text);
}

void BM_cli_cold(benchmark::State& state, const char* map_name, const char* hemisphere) {
    for (auto _ : state) state.SetIterationTime(cold_seconds(map_name, hemisphere));
}

void BM_cli_warm(benchmark::State& state, const char* map_name, const char* hemisphere) {
    use_cli_malloc_settings();
    const EnvironmentMap map = load_environment(std::string(kWorld) + map_name + ".exr");
    const DecomposeOptions options = cli_options(parse_enum<Hemisphere>(hemisphere));
    Decomposition d;
    for (auto _ : state) {
        d = decompose(map, options);
        benchmark::DoNotOptimize(d.cells.data());
    }
    state.counters["iterations"] = d.iterations;
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

int main(int argc, char** argv) {
    using namespace envshadow;
    if (argc == 4 && std::strcmp(argv[1], "--cold") == 0) return run_cold(argv[2], argv[3]);
    for (const char* map : kMaps)
        for (const char* hemisphere : {"full", "upper"}) {
            const std::string name = std::string(map) + "/" + hemisphere;
            benchmark::RegisterBenchmark(("BM_cli_cold/" + name).c_str(), BM_cli_cold, map, hemisphere)
                ->Unit(benchmark::kMillisecond)
                ->UseManualTime()
                ->Iterations(5);
            benchmark::RegisterBenchmark(("BM_cli_warm/" + name).c_str(), BM_cli_warm, map, hemisphere)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
        }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
