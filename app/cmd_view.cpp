#include "commands.h"

#include <filesystem>

#include "core/error.h"
#include "gl/context.h"
#include "viewer/viewer.h"

namespace envshadow::app {

Command add_view_command(CLI::App& parent) {
    auto options = std::make_shared<ViewerOptions>();
    CLI::App* app = parent.add_subcommand("view", "Interactive viewer (GLFW window, Dear ImGui); press H for help");
    options->common.width = 1600;
    options->common.height = 900;
    CommonOptionSet set;
    set.scene_required = false;  // assets/scenes/default.json
    set.backend = false;         // a window
    add_common_options(app, &options->common, set);
    app->add_option("--speed", options->speed,
                    "Animation seconds per second (0 pauses; builtin:sky's sun: one hour per second)")
        ->check(CLI::Range(0.0f, 100.0f));
    add_time_option(app, &options->time);
    add_pass_timing_option(app, &options->pass_timing);
    add_setting_options(app, &options->settings, command_defaults());
    add_tonemap_option(app, &options->tonemap);
    app->add_option("--target-ms", options->target_ms,
                    "While the view changes, shade at the fraction of the window that holds this frame time; "
                    "full size once still (0: always full size; default 100)")
        ->check(CLI::Range(0.0, 10000.0));
    app->add_option("--orbit-frames", options->orbit_frames,
                    "Automated runs: orbit the camera for the first F frames (once the map is lit) as a left-button "
                    "drag would, then "
                    "hold still; logs the frame times and scales while moving")
        ->check(CLI::Range(0, 1000000));
    app->add_option("--frames", options->frames, "Quit after this many frames (automated runs)")
        ->check(CLI::Range(1, 1000000));
    app->add_option("--screenshot", options->screenshot, "With --frames: write the window, UI included, to this PNG");
    return {app, [options] {
                if (options->common.scene.empty()) options->common.scene = ENVSHADOW_DEFAULT_SCENE;
                // Bad values fail before the window opens.
                parse_fs_importance(options->common.fs_importance);
                settings_from(options->settings, command_defaults());
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
