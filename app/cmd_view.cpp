#include "commands.h"

#include <filesystem>

#include "core/error.h"
#include "gl/context.h"
#include "viewer/viewer.h"

namespace envshadow::app {

Command add_view_command(CLI::App& parent) {
    auto options = std::make_shared<ViewerOptions>();
    CLI::App* app = parent.add_subcommand("view", "Interactive viewer (GLFW window, Dear ImGui); press H for help");
    app->add_option("--scene", options->scene, "Scene JSON or .gltf/.glb (default: assets/scenes/default.json)");
    app->add_option("--env", options->environment, "Environment map (.exr, .hdr or builtin:…), overrides the scene's");
    app->add_option("--lights", options->lights, "Number of cells N")->check(CLI::Range(1, 256));
    app->add_option(
           "--method", options->method,
           "Decomposition: lloyd, ccvt, mediancut, random, fs; or fs-gpu (lights sampled on the GPU every frame; "
           "G toggles)")
        ->check(CLI::IsMember({"lloyd", "ccvt", "mediancut", "random", "fs", "fs-gpu"}));
    app->add_option("--seed", options->seed, "Seed of the decomposition");
    app->add_option("--speed", options->speed,
                    "Animation seconds per second (0 pauses; builtin:sky's sun: one hour per second)")
        ->check(CLI::Range(0.0f, 100.0f));
    app->add_option("--time", options->time, "Animation time at the start, in seconds")->check(CLI::Range(-1e6, 1e6));
    app->add_option("--width", options->width, "Window width")->check(CLI::Range(320, 8192));
    app->add_option("--height", options->height, "Window height")->check(CLI::Range(240, 8192));
    add_pass_timing_option(app, &options->pass_timing);
    app->add_option("--frames", options->frames, "Quit after this many frames (automated runs)")
        ->check(CLI::Range(1, 1000000));
    app->add_option("--screenshot", options->screenshot, "With --frames: write the window, UI included, to this PNG");
    return {app, [options] {
                if (options->scene.empty()) options->scene = ENVSHADOW_DEFAULT_SCENE;
                if (!options->screenshot.empty() && options->frames == 0)
                    throw UsageError("--screenshot needs --frames (the window is captured after the last frame)");
                if (!gl::display_available())
                    throw PlatformError(
                        "view: no display (DISPLAY and WAYLAND_DISPLAY are unset); run under xvfb-run, "
                        "or use 'envshadow render' for off-screen images");
                return run_viewer(*options);
            }};
}

}  // namespace envshadow::app
