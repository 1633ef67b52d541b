#pragma once
// `envshadow view`: the interactive viewer (GLFW window, Dear ImGui).
#include <cstdint>
#include <string>

namespace envshadow::app {

struct ViewerOptions {
    std::string scene;        // scene JSON or .gltf/.glb; empty: assets/scenes/default.json
    std::string environment;  // overrides the scene's environment when set
    int lights = 128;
    std::string method = "lloyd";  // or "fs-gpu": lights sampled on the GPU every frame
    std::uint64_t seed = 1;
    float speed = 1.0f;  // animation seconds per second of wall time (0: paused)
    double time = 0.0;   // animation time at the start (seconds)
    int width = 1600, height = 900;
    int frames = 0;                    // > 0: quit after this many frames (automated runs)
    std::string screenshot;            // with frames: the window, UI included, written here at the end
    std::string pass_timing = "auto";  // gl::parse_pass_timing
};

int run_viewer(const ViewerOptions& options);

}  // namespace envshadow::app
