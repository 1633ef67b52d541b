#include "viewer/dynamic_resolution.h"

#include <cmath>

namespace envshadow::app {

void DynamicResolution::set_options(const DynamicResolutionOptions& options) {
    options_ = options;
    options_.min_scale = std::clamp(options_.min_scale, kStep, 1.0f);
    moving_scale_ = std::clamp(moving_scale_, options_.min_scale, 1.0f);
}

float DynamicResolution::quantized(float scale) const {
    const float steps = std::floor(scale / kStep + 1e-4f);
    return std::clamp(steps * kStep, options_.min_scale, 1.0f);
}

float DynamicResolution::scale_for_frame(bool changing, double now_seconds) {
    if (changing) last_change_ = now_seconds;
    const bool still = now_seconds - last_change_ >= options_.settle_seconds;
    full_ = still || !options_.enabled;
    return full_ ? 1.0f : quantized(moving_scale_);
}

void DynamicResolution::record(float scale, double frame_ms) {
    if (!options_.enabled || !(frame_ms > 0.0) || !std::isfinite(frame_ms)) return;
    // Shading cost goes with the pixels, scale^2: the scale that would have met the target, with
    // the step limited (a frame of other work, a compile or a new map, must not collapse it) and
    // slower upward than downward, so that it settles under the target rather than around it.
    const double wanted = double(scale) * std::sqrt(options_.target_ms / frame_ms);
    const double next = std::clamp(wanted, double(moving_scale_) * 0.5, double(moving_scale_) * 1.15);
    moving_scale_ = std::clamp(float(next), options_.min_scale, 1.0f);
}

}  // namespace envshadow::app
