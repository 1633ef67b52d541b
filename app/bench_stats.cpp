#include "bench_stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "core/error.h"

namespace envshadow::app {
namespace {
double quantile(const std::vector<double>& sorted, double q) {
    const double position = q * double(sorted.size() - 1);
    const size_t lo = size_t(std::floor(position)), hi = size_t(std::ceil(position));
    return sorted[lo] + (sorted[hi] - sorted[lo]) * (position - double(lo));
}

int parse_positive(const std::string& text, const std::string& spec) {
    size_t used = 0;
    int value = 0;
    try {
        value = std::stoi(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || value <= 0)
        throw UsageError("--sweep " + spec + ": '" + text + "' is not a positive integer");
    return value;
}
}  // namespace

TimeSummary summarize(std::vector<double> samples) {
    TimeSummary s;
    if (samples.empty()) return s;
    std::sort(samples.begin(), samples.end());
    s.median = quantile(samples, 0.5);
    s.p95 = quantile(samples, 0.95);
    s.mean = std::accumulate(samples.begin(), samples.end(), 0.0) / double(samples.size());
    s.min = samples.front();
    s.max = samples.back();
    return s;
}

std::vector<SweepPoint> parse_sweep(const std::string& spec) {
    const size_t eq = spec.find('=');
    if (eq == std::string::npos || eq + 1 >= spec.size())
        throw UsageError("--sweep '" + spec + "': expected lights=…, resolution=WxH,… or tile=…");
    const std::string key = spec.substr(0, eq);
    if (key != "lights" && key != "resolution" && key != "tile")
        throw UsageError("--sweep '" + spec + "': unknown key '" + key + "' (lights, resolution or tile)");
    std::vector<SweepPoint> points;
    std::stringstream values(spec.substr(eq + 1));
    for (std::string value; std::getline(values, value, ',');) {
        SweepPoint p;
        p.label = key + "=" + value;
        if (key == "lights") {
            p.lights = parse_positive(value, spec);
        } else if (key == "tile") {
            p.tile = parse_positive(value, spec);
        } else {
            const size_t x = value.find('x');
            if (x == std::string::npos) throw UsageError("--sweep " + spec + ": '" + value + "' is not WxH");
            p.width = parse_positive(value.substr(0, x), spec);
            p.height = parse_positive(value.substr(x + 1), spec);
        }
        points.push_back(p);
    }
    if (points.empty()) throw UsageError("--sweep '" + spec + "': no values");
    return points;
}

}  // namespace envshadow::app
