// Times the prefiltering of the ratio estimator (env/prefilter.h, docs/DESIGN.md §4.1) on the 1024 x 512
// photographs city and courtyard, whole sphere and upper hemisphere (a scene with a ground):
//   build/tests/bench/bench_prefilter [--benchmark_repetitions=5 --benchmark_report_aggregates_only=true]
// Wall time (UseRealTime: load time is what a user waits for) and the CPU time of all threads (the
// prefiltering is parallel, TBB), which a loaded machine changes less.
#include <benchmark/benchmark.h>

#include <string>

#include "env/environment.h"
#include "env/importance.h"
#include "env/prefilter.h"

namespace envshadow {
namespace {

const char* const kWorld = "/usr/share/blender/datafiles/studiolights/world/";

const EnvironmentMap& world(const std::string& name) {
    static const EnvironmentMap city = load_environment(std::string(kWorld) + "city.exr");
    static const EnvironmentMap courtyard = load_environment(std::string(kWorld) + "courtyard.exr");
    return name == "city" ? city : courtyard;
}

void BM_prefilter(benchmark::State& state, const char* map_name, Hemisphere hemisphere) {
    const EnvironmentMap& map = world(map_name);
    for (auto _ : state) {
        PrefilteredEnvironment env = prefilter_environment(map, hemisphere);
        benchmark::DoNotOptimize(env.levels.data());
    }
}

BENCHMARK_CAPTURE(BM_prefilter, city_full, "city", Hemisphere::full)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_prefilter, city_upper, "city", Hemisphere::upper)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_prefilter, courtyard_full, "courtyard", Hemisphere::full)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_prefilter, courtyard_upper, "courtyard", Hemisphere::upper)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace
}  // namespace envshadow

BENCHMARK_MAIN();
