#pragma once
// Each subcommand registers its options on the parent CLI11 app and returns what to run once the
// command line has been parsed. `run` returns the exit code; errors are thrown (core/error.h) and
// mapped to exit codes by main(): UsageError 2, InputError 3, PlatformError 4.
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "render/render_settings.h"

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

// --pass-timing, for the commands that render; gl::parse_pass_timing reads the value.
inline void add_pass_timing_option(CLI::App* app, std::string* value) {
    app->add_option("--pass-timing", *value,
                    "auto (default: wait on a software rasteriser, queries on a GPU), queries (GL_TIME_ELAPSED) or "
                    "wait (glFinish around each pass)")
        ->check(CLI::IsMember({"auto", "queries", "wait"}));
}

// --baseline, --caster-lod, --prepass: issue 10's optimisations, for render and bench.
struct OptimisationFlags {
    bool baseline = false;
    std::string caster_lod, prepass;  // empty: the default
};

inline void add_optimisation_options(CLI::App* app, OptimisationFlags* flags) {
    app->add_flag("--baseline", flags->baseline, "The first working renderer: every issue-10 optimisation off");
    app->add_option("--caster-lod", flags->caster_lod, "Shadow-caster LOD error in shadow texels (default 0.3), or off")
        ->type_name("F|off");
    app->add_option("--prepass", flags->prepass, "Depth pre-pass before shading: on (default) or off")
        ->check(CLI::IsMember({"on", "off"}));
}

// `settings` with the flags applied (baseline first); UsageError for a bad value.
inline render::RenderSettings apply(const OptimisationFlags& flags, render::RenderSettings settings) {
    if (flags.baseline) settings = render::baseline(settings);
    if (!flags.caster_lod.empty())
        settings = render::apply_variant(settings, "caster-lod=" + flags.caster_lod, "--caster-lod");
    if (!flags.prepass.empty()) settings = render::apply_variant(settings, "prepass=" + flags.prepass, "--prepass");
    return settings;
}

// `envshadow --version`: version, GL renderer per backend, backend availability.
int print_version();

// For subcommands whose implementation has not landed yet: says so, exit code 2.
int not_built(const char* name);

}  // namespace envshadow::app
