#include "commands.h"

namespace envshadow::app {

Command add_view_command(CLI::App& parent) {
    CLI::App* app = parent.add_subcommand("view", "Interactive viewer (GLFW window, Dear ImGui)");
    app->allow_extras();
    return {app, [] { return not_built("view"); }};
}

}  // namespace envshadow::app
