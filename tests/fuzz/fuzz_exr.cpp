// libFuzzer target: load_environment on one .exr file (read_exr in engine/core, then the map's shape
// and texel checks in engine/env).
#include <cstddef>
#include <cstdint>

#include "env/environment.h"
#include "fuzz_limits.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace envshadow;
    const auto path = fuzz::write_input("input.exr", data, size);
    if (fuzz::exr_declares_a_huge_image(path)) return 0;
    try {
        fuzz::check_environment(load_environment(path.string()));
    } catch (const InputError& e) {
        fuzz::check_error_message(e, path);
    }
    return 0;
}
