// libFuzzer target: load_environment on one Radiance .hdr file (read_radiance_hdr in engine/core,
// then the map's shape and texel checks in engine/env). No size filter is needed: the reader refuses
// a file too short for its declared size before allocating.
#include <cstddef>
#include <cstdint>

#include "env/environment.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace envshadow;
    const auto path = fuzz::write_input("input.hdr", data, size);
    try {
        fuzz::check_environment(load_environment(path.string()));
    } catch (const InputError& e) {
        fuzz::check_error_message(e, path);
    }
    return 0;
}
