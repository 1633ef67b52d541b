#pragma once
// Statistics and sweep parsing for `envshadow bench` (GL-free, tested).
#include <string>
#include <vector>

namespace envshadow::app {

struct TimeSummary {
    double median = 0.0;
    double p95 = 0.0;
    double mean = 0.0;
    double min = 0.0;
    double max = 0.0;
};

// Median and 95th percentile by linear interpolation between order statistics (the "R-7" rule).
TimeSummary summarize(std::vector<double> samples);

// One setting of a sweep. Unset fields keep the command-line values.
struct SweepPoint {
    int lights = 0;
    int width = 0, height = 0;
    int tile = 0;
    std::string label;  // "lights=64", "resolution=1280x720"
};

// "lights=16,32,64", "resolution=640x360,1920x1080", "tile=128,256". Throws UsageError.
std::vector<SweepPoint> parse_sweep(const std::string& spec);

}  // namespace envshadow::app
