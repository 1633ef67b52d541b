// envshadow: image-based lighting with shadows (Barsi, Szirmay-Kalos, Szécsi).
// Parse the command line, run the chosen subcommand, turn errors into one line and an exit code.
#include <cstdio>
#include <exception>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <CLI/CLI.hpp>

#include "commands.h"
#include "core/error.h"

int main(int argc, char** argv) {
    using namespace envshadow;
#if defined(__GLIBC__)
    // Buffers of up to 32 MB come from the heap and stay mapped once freed, so that the decomposition
    // reuses the pages the map's loading touched instead of faulting in fresh ones (docs/PERFORMANCE.md).
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
#endif
    CLI::App cli("envshadow: real-time image-based lighting with shadows", "envshadow");
    cli.require_subcommand(0, 1);
    bool version = false;
    cli.add_flag("--version", version, "Print the version, the GL renderer of each backend and which backends work");

    std::vector<app::Command> commands = {app::add_decompose_command(cli), app::add_render_command(cli),
                                          app::add_bench_command(cli),     app::add_reference_command(cli),
                                          app::add_compare_command(cli),   app::add_view_command(cli)};

    try {
        cli.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return cli.exit(e);
    } catch (const CLI::ParseError& e) {  // one line, like every other error
        std::fprintf(stderr, "envshadow: %s (run with --help for usage)\n", one_line_text(e.what()).c_str());
        return 2;
    }

    try {
        if (version) return app::print_version();
        for (const app::Command& command : commands)
            if (command.app->parsed()) return command.run();
        std::fputs(cli.help().c_str(), stderr);
        return 2;
    } catch (const UsageError& e) {
        std::fprintf(stderr, "envshadow: %s\n", e.what());
        return 2;
    } catch (const InputError& e) {
        std::fprintf(stderr, "envshadow: %s\n", e.what());
        return 3;
    } catch (const PlatformError& e) {
        std::fprintf(stderr, "envshadow: %s\n", e.what());
        return 4;
    } catch (const Interrupted& e) {
        std::fprintf(stderr, "envshadow: %s, nothing written\n", e.what());
        return 130;  // the shell's code for a command stopped by SIGINT
    } catch (const std::exception& e) {
        std::fprintf(stderr, "envshadow: internal error: %s\n", e.what());
        return 1;
    }
}
