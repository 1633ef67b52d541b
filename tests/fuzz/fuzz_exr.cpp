// libFuzzer target: read_exr (engine/core) on one .exr file.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/image.h"
#include "fuzz_support.h"
#include "fuzz_limits.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace envshadow;
    const auto path = fuzz::write_input("input.exr", data, size);
    if (fuzz::exr_declares_a_huge_image(path)) return 0;
    try {
        const ExrContents contents = read_exr(path);
        const Image& image = contents.image;
        if (image.width < 1 || image.height < 1 || image.width > kMaxImageWidth || image.height > kMaxImageHeight)
            fuzz::finding("image size outside the limits");
        if (image.pixels.size() != std::size_t(image.width) * std::size_t(image.height))
            fuzz::finding("pixel count does not match the size");
    } catch (const InputError& e) {
        fuzz::check_error_message(e, path);
    }
    return 0;
}
