#include "commands.h"

namespace envshadow::app {

Command add_decompose_command(CLI::App& parent) {
    CLI::App* app = parent.add_subcommand("decompose", "Cut an environment map into N directional cells");
    app->allow_extras();
    return {app, [] { return not_built("decompose"); }};
}

}  // namespace envshadow::app
