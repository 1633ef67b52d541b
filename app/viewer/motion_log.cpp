#include "viewer/motion_log.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/enum_names.h"

namespace envshadow::app {
namespace {

double median_of(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    return values.empty() ? 0.0 : values[values.size() / 2];
}

}  // namespace

void MotionLog::record(const DrawnFrame& frame, double ms, double now) {
    if (frame.changing) {
        frame_ms.push_back(ms);
        render_ms.push_back(frame.render_ms);
        atlas_passes += frame.atlas_passes;
        for (const gl::PassTime& pass : frame.passes) {
            if (!pass_ms.contains(pass.pass)) pass_order.push_back(pass.pass);
            pass_ms[pass.pass].push_back(pass.milliseconds);
        }
        scales.push_back(frame.scale);
        last_moving = frame;
        stopped_at = now;
        full_again.reset();
    } else if (frame.scale == 1.0f && stopped_at && !full_again) {
        full_again = now - *stopped_at;
    }
}

std::string MotionLog::summary(const DynamicResolutionOptions& options) const {
    const double ms = median_of(frame_ms);
    const std::vector<double> scale_values(scales.begin(), scales.end());
    char text[400];
    std::snprintf(text, sizeof text,
                  "dynamic resolution: %zu frames while the view changed, median %.1f ms (%.1f FPS) at scale "
                  "%.2f, the last at %dx%d, %d sample(s) per pixel, %s shadows; target %s",
                  frame_ms.size(), ms, ms > 0.0 ? 1000.0 / ms : 0.0, median_of(scale_values), last_moving.width,
                  last_moving.height, last_moving.samples,
                  std::string(envshadow::to_string(last_moving.shadows)).c_str(),
                  options.enabled ? (std::to_string(int(std::lround(options.target_ms))) + " ms").c_str() : "off");
    std::string line = text;
    if (full_again) {
        std::snprintf(text, sizeof text, "; full size again %.2f s after it stopped", *full_again);
        line += text;
    } else {
        line += "; not back at full size when the run ended";
    }
    std::snprintf(text, sizeof text, "; while it changed: the renderer %.1f ms a frame (median), %d atlas passes",
                  median_of(render_ms), atlas_passes);
    line += text;
    for (const std::string& pass : pass_order) {
        std::snprintf(text, sizeof text, ", %s %.1f", pass.c_str(), median_of(pass_ms.at(pass)));
        line += text;
    }
    if (!pass_order.empty()) line += " ms (medians of the frames that had the pass)";
    return line;
}

}  // namespace envshadow::app
