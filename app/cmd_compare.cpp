#include "commands.h"

namespace envshadow::app {

Command add_compare_command(CLI::App& parent) {
    CLI::App* app = parent.add_subcommand("compare", "Relative RMSE and PSNR of two EXR images over object pixels");
    app->allow_extras();
    return {app, [] { return not_built("compare"); }};
}

}  // namespace envshadow::app
