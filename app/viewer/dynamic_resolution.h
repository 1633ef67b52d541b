#pragma once
// Dynamic resolution for the viewer (docs/DESIGN.md §5.10): while the view changes (the camera is
// dragged, the animation plays) the frame is shaded at a fraction of the window that holds a
// frame-time target; once the view has been still for a moment, at the window's full size.
// Pure bookkeeping on times the viewer measures, so it is tested without a window.
#include <algorithm>
#include <limits>

namespace envshadow::app {

struct DynamicResolutionOptions {
    bool enabled = true;
    double target_ms = 100.0;     // frame time to hold while the view changes
    double settle_seconds = 0.3;  // still for this long: back to full size
    float min_scale = 0.25f;      // of the window's width and height
    // One sample per pixel while the view changes, whatever --msaa says: on a CPU rasteriser such as
    // llvmpipe 4 samples cost about 3x the shading (docs/PERFORMANCE.md).
    bool one_sample_while_moving = true;
    // Hard shadows while the view changes, whatever --shadows says: the soft shadows' blocker search and
    // filter cost about 3.5x the cells' one lookup each (docs/PERFORMANCE.md).
    bool hard_shadows_while_moving = true;
};

class DynamicResolution {
public:
    // Scales are multiples of this step, so that the render targets change size only now and then.
    static constexpr float kStep = 1.0f / 16.0f;

    explicit DynamicResolution(DynamicResolutionOptions options = {}) : options_(options) {}

    const DynamicResolutionOptions& options() const { return options_; }
    void set_options(const DynamicResolutionOptions& options);

    // The scale to shade the next frame at; `changing`: the view differs from the last frame's.
    float scale_for_frame(bool changing, double now_seconds);
    // How long the frame shaded at `scale` took, start to start: steers the scale of moving frames.
    void record(float scale, double frame_ms);

    // The scale that holds the target while moving, as last estimated.
    float moving_scale() const { return quantized(moving_scale_); }
    // The view is still and shaded at full size.
    bool at_full_quality() const { return full_; }

private:
    float quantized(float scale) const;

    DynamicResolutionOptions options_;
    float moving_scale_ = 1.0f;  // continuous; quantized when used
    double last_change_ = -std::numeric_limits<double>::infinity();
    bool full_ = true;
};

}  // namespace envshadow::app
