#include "commands.h"

namespace envshadow::app {

Command add_reference_command(CLI::App& parent) {
    CLI::App* app = parent.add_subcommand("reference", "Render the ground truth with Embree (CPU)");
    app->allow_extras();
    return {app, [] { return not_built("reference"); }};
}

}  // namespace envshadow::app
