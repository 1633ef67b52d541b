#pragma once
// Inputs that are valid but too big to fuzz quickly: a picture within the loader's limits
// (16384 x 16384) can take 4 GiB and seconds to fill, and even a megapixel one slows fuzzing to a few
// inputs a second. The harness skips them; the loaders' own limit checks still see every declared
// size above their limits.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/image.h"

namespace envshadow::fuzz {

inline constexpr long long kMaxFuzzPixels = 1 << 16;  // 1 MiB of RGBA float

inline bool within_limits_but_huge(long long width, long long height) {
    return width > 0 && height > 0 && width <= kMaxImageWidth && height <= kMaxImageHeight &&
           width * height > kMaxFuzzPixels;
}

// Reads the first header's dataWindow attribute by hand (OpenEXR's layout: magic, version, then
// "name\0type\0" + int32 size + value, until an empty name).
inline bool exr_declares_a_huge_image(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::size_t at = 8;
    auto read_string = [&](std::string& out) {
        const auto end = std::find(bytes.begin() + std::ptrdiff_t(std::min(at, bytes.size())), bytes.end(), '\0');
        if (end == bytes.end()) return false;
        out.assign(bytes.begin() + std::ptrdiff_t(at), end);
        at = std::size_t(end - bytes.begin()) + 1;
        return true;
    };
    while (at < bytes.size()) {
        std::string name, type;
        if (!read_string(name) || name.empty() || !read_string(type) || at + 4 > bytes.size()) return false;
        std::int32_t size;
        std::memcpy(&size, &bytes[at], 4);
        at += 4;
        if (size < 0 || std::size_t(size) > bytes.size() - at) return false;
        if (name == "dataWindow" && size == 16) {
            std::int32_t box[4];
            std::memcpy(box, &bytes[at], 16);
            return within_limits_but_huge(1ll + box[2] - box[0], 1ll + box[3] - box[1]);
        }
        at += std::size_t(size);
    }
    return false;
}

}  // namespace envshadow::fuzz
