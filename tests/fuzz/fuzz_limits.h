#pragma once
// Inputs that are valid but too big to fuzz quickly: a map within the loader's limits
// (16384 x 8192) can take 2 GiB and seconds to fill, and even a megapixel one slows fuzzing to a few
// inputs a second. The harness skips them; the loaders' own checks still see every other declared
// size (above the picture limits, or not 2:1: load_environment refuses those before allocating).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/image.h"
#include "env/environment.h"

namespace envshadow::fuzz {

inline constexpr long long kMaxFuzzPixels = 1 << 16;  // 1 MiB of RGBA float

inline bool a_map_but_huge(long long width, long long height) {
    return height > 0 && width == 2 * height && width <= kMaxEnvironmentWidth && width * height > kMaxFuzzPixels;
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
            return a_map_but_huge(1ll + box[2] - box[0], 1ll + box[3] - box[1]);
        }
        at += std::size_t(size);
    }
    return false;
}

}  // namespace envshadow::fuzz
