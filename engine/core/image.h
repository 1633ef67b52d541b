#pragma once
// Linear HDR images (RGBA float) and their two output forms: EXR (linear) and PNG (exposure,
// a tone map (core/tonemap.h), sRGB). Used by every layer that reads or writes pictures; no GL here.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include <glm/vec4.hpp>

#include "core/tonemap.h"

namespace envshadow {

// Row 0 is the top of the picture (as in files); pixel (x, y) is pixels[y * width + x].
struct Image {
    int width = 0;
    int height = 0;
    std::vector<glm::vec4> pixels;

    Image() = default;
    Image(int w, int h, glm::vec4 fill = glm::vec4(0.0f)) : width(w), height(h), pixels(size_t(w) * size_t(h), fill) {}
    glm::vec4& at(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
    const glm::vec4& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
    bool empty() const { return pixels.empty(); }
};

// 8-bit RGBA, row 0 at the top.
struct Image8 {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;

    Image8() = default;
    Image8(int w, int h) : width(w), height(h), rgba(size_t(w) * size_t(h) * 4, 0) {}
    std::uint8_t* at(int x, int y) { return &rgba[(size_t(y) * size_t(width) + size_t(x)) * 4]; }
    const std::uint8_t* at(int x, int y) const { return &rgba[(size_t(y) * size_t(width) + size_t(x)) * 4]; }
};

// Largest picture any loader accepts (README "Input limits").
inline constexpr int kMaxImageWidth = 16384;
inline constexpr int kMaxImageHeight = 16384;

struct ExrContents {
    Image image;  // missing A reads as 1
    bool had_alpha = false;
};

// A caller's own limit on a picture's size (e.g. the environment loader's 2:1 shape), called by the
// readers with the declared width and height once the header is read (and found within
// kMaxImageWidth x kMaxImageHeight), before anything the size of the picture is allocated. It throws
// (InputError) to refuse the picture.
using ImageSizeCheck = std::function<void(int width, int height)>;

// Reads any OpenEXR file with R, G, B channels (half, float or uint; scanline or tiled; any
// compression). Throws InputError naming the file and the reason.
ExrContents read_exr(const std::filesystem::path& path, const ImageSizeCheck& check_size = {});

// Reads a Radiance RGBE (.hdr) file: run-length or flat scanlines, "-Y H +X W" layout; A reads as
// 1. Throws InputError naming the file and the reason (truncation, bad run lengths, sizes).
Image read_radiance_hdr(const std::filesystem::path& path, const ImageSizeCheck& check_size = {});

// Writes RGBA float EXR (ZIP compressed), atomically.
void write_exr(const std::filesystem::path& path, const Image& image);

// Writes an 8-bit RGBA PNG, atomically.
void write_png(const std::filesystem::path& path, const Image8& image);

// Reads a PNG (or any 8-bit format stb_image knows) as RGBA. Throws InputError.
Image8 read_png(const std::filesystem::path& path);

// Exposure (in stops), the tone map `op` (core/tonemap.h; ACES filmic by default) and the sRGB
// transfer function. Non-finite channels count as 0. Alpha is copied (clamped to [0, 1]).
Image8 tonemap_to_srgb8(const Image& linear, float exposure_stops = 0.0f, ToneMap op = ToneMap::aces);

float srgb_encode(float linear);

}  // namespace envshadow
