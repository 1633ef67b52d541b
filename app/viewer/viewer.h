#pragma once
// `envshadow view`: the interactive viewer (GLFW window, Dear ImGui).
#include <string>

#include "options.h"

namespace envshadow::app {

struct ViewerOptions {
    // --scene (empty: assets/scenes/default.json), --env, --lights, --method (or the GPU sampler's
    // name: lights sampled every frame), --seed, --width and --height of the window (view: 1600x900).
    CommonOptions common;
    float speed = 1.0f;                // animation seconds per second of wall time (0: paused)
    double time = 0.0;                 // animation time at the start (seconds)
    int frames = 0;                    // > 0: quit after this many frames (automated runs)
    std::string screenshot;            // with frames: the window, UI included, written here at the end
    double target_ms = 100.0;          // --target-ms: dynamic resolution's frame time (0: off)
    int orbit_frames = 0;              // --orbit-frames: a synthetic drag over the first frames
    std::string pass_timing = "auto";  // pass_timing()
    SettingOptions settings;           // --shading, --msaa, ... (render::setting_table()), --baseline
    std::string tonemap = "aces";      // --tonemap: the window's and the screenshot PNG's (tone_map_option())
};

int run_viewer(const ViewerOptions& options);

}  // namespace envshadow::app
