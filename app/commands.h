#pragma once
// Each subcommand registers its options on the parent CLI11 app and returns what to run once the
// command line has been parsed. `run` returns the exit code; errors are thrown (core/error.h) and
// mapped to exit codes by main(): UsageError 2, InputError 3, PlatformError 4.
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "options.h"

namespace envshadow::app {

struct Command {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

Command add_decompose_command(CLI::App& parent);
Command add_render_command(CLI::App& parent);
Command add_bench_command(CLI::App& parent);
Command add_reference_command(CLI::App& parent);
Command add_compare_command(CLI::App& parent);
Command add_view_command(CLI::App& parent);

// `envshadow --version`: version, GL renderer per backend, backend availability.
int print_version();

}  // namespace envshadow::app
