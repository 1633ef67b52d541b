#include <cstdio>

#include "commands.h"
#include "gl/context.h"

namespace envshadow::app {

int print_version() {
    std::printf("envshadow %s\n", ENVSHADOW_VERSION);
    for (const gl::BackendProbe& probe : gl::probe_backends())
        std::printf("  %-7s %s: %s\n", std::string(gl::to_string(probe.backend)).c_str(),
                    probe.available ? "yes" : "no ", probe.detail.c_str());
    return 0;
}

}  // namespace envshadow::app
