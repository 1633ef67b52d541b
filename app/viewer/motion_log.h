#pragma once
// The viewer's record of the frames drawn while the view changed (a drag, the animation): how fast, at
// what size, and how soon a full-size frame followed once it stopped. Its summary is the log line at
// the end of a run, which automated runs (--orbit-frames) read.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gl/timer.h"
#include "render/render_settings.h"
#include "viewer/dynamic_resolution.h"

namespace envshadow::app {

// What a frame was drawn with, for the frame-time bookkeeping once the next one starts.
struct DrawnFrame {
    bool changing = false;  // the view differed from the frame before
    float scale = 1.0f;     // of the window's size
    int width = 0, height = 0;
    int samples = 1;                                        // MSAA samples asked of the renderer
    render::ShadowMode shadows = render::ShadowMode::hard;  // asked of the renderer
    double render_ms = 0.0;  // Renderer::render's wall time: the rest of the frame is display, panels, swap
    int atlas_passes = 0;    // 0 when the shadow cache kept the atlas (docs/DESIGN.md §5.11)
    std::vector<gl::PassTime> passes;
};

struct MotionLog {
    std::vector<double> frame_ms;
    std::vector<double> render_ms;
    std::map<std::string, std::vector<double>> pass_ms;  // per pass, in the order first seen
    std::vector<std::string> pass_order;
    std::vector<float> scales;
    int atlas_passes = 0;
    DrawnFrame last_moving;
    std::optional<double> stopped_at;  // the end of the last frame whose view changed (steady seconds)
    std::optional<double> full_again;  // seconds from stopped_at to the end of the first full-size frame

    // `frame`, which took `ms` and ended at `now` (steady seconds).
    void record(const DrawnFrame& frame, double ms, double now);
    // "dynamic resolution: N frames while the view changed, median ..." (frame_ms not empty).
    std::string summary(const DynamicResolutionOptions& options) const;
};

}  // namespace envshadow::app
