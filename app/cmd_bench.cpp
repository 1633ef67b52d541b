#include "commands.h"

namespace envshadow::app {

Command add_bench_command(CLI::App& parent) {
    CLI::App* app = parent.add_subcommand("bench", "Measure frame times (GPU timer queries per pass)");
    app->allow_extras();
    return {app, [] { return not_built("bench"); }};
}

}  // namespace envshadow::app
