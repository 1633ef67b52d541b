// libFuzzer target: read_radiance_hdr (engine/core) on one .hdr file. No size filter is needed: the
// reader refuses a file too short for its declared size before allocating.
#include <cstddef>
#include <cstdint>

#include "core/image.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace envshadow;
    const auto path = fuzz::write_input("input.hdr", data, size);
    try {
        const Image image = read_radiance_hdr(path);
        if (image.width < 1 || image.height < 1 || image.width > kMaxImageWidth || image.height > kMaxImageHeight)
            fuzz::finding("image size outside the limits");
        if (image.pixels.size() != std::size_t(image.width) * std::size_t(image.height))
            fuzz::finding("pixel count does not match the size");
        for (const glm::vec4& p : image.pixels)
            if (!(p.r >= 0.0f && p.g >= 0.0f && p.b >= 0.0f) || !std::isfinite(p.r) || !std::isfinite(p.g) ||
                !std::isfinite(p.b))
                fuzz::finding("RGBE decoded to a negative or non-finite value");
    } catch (const InputError& e) {
        fuzz::check_error_message(e, path);
    }
    return 0;
}
