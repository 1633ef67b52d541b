#include "core/image.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace envshadow {
namespace {

// Walks the first header's attributes (magic, version, then "name\0type\0" + int32 size + value
// until an empty name) before OpenEXR does: OpenEXR allocates whatever an attribute declares (a
// 240-byte file can ask for 2 GB), buffers whole tiles or chunks of up to 256 lines of every channel,
// and reads the offset table of every tile, all before any size could be checked. Throws InputError
// for attributes past the end of the file, a missing data window or channel list, sizes out of
// limits, chunk buffers over 1 GiB, tiles larger than both the picture and 1 M texels, or an offset
// table larger than the file.
// `check_size` (the caller's own limit) sees the data window's size as soon as it is known to be
// within limits, before the chunk and offset-table checks and long before any pixel buffer.
void check_exr_header(const std::filesystem::path& path, const std::string& name, const ImageSizeCheck& check_size) {
    constexpr std::uint64_t kMaxChunkBytes = 1ull << 30;
    constexpr std::int32_t kMaxChannelListBytes = 1 << 20;
    constexpr std::uint64_t kMaxTileOverhang = 1 << 20;  // texels a tile may have beyond the picture's
    std::ifstream in(path, std::ios::binary);
    std::error_code ec;
    const std::uintmax_t file_size = std::filesystem::file_size(path, ec);
    const auto corrupt = [&](const std::string& reason) { return InputError(name + ": " + reason); };
    char magic[8];
    if (!in.read(magic, 8) || std::memcmp(magic, "\x76\x2f\x31\x01", 4) != 0)
        throw corrupt("not an OpenEXR file (bad magic number)");
    auto read_string = [&](std::string& out) {
        out.clear();
        for (char c; in.get(c);) {
            if (c == '\0') return true;
            if (out.size() >= 255) return false;  // OpenEXR's longest attribute name or type
            out += c;
        }
        return false;
    };

    long long width = -1, height = -1;
    std::uint64_t bytes_per_pixel = 0;
    std::uint32_t tile[2] = {0, 0};
    for (std::string attribute, type;;) {
        if (!read_string(attribute)) throw corrupt("truncated or corrupt OpenEXR header");
        if (attribute.empty()) break;
        std::int32_t size = 0;
        if (!read_string(type) || !in.read(reinterpret_cast<char*>(&size), 4))
            throw corrupt("truncated or corrupt OpenEXR header");
        const auto at = static_cast<std::uintmax_t>(in.tellg());
        if (size < 0 || std::uintmax_t(size) > file_size - std::min(at, file_size))
            throw corrupt("OpenEXR header attribute '" + attribute + "' claims " + std::to_string(size) +
                          " bytes, more than the file holds");
        if (attribute == "dataWindow" && type == "box2i" && size == 16) {
            std::int32_t box[4];
            in.read(reinterpret_cast<char*>(box), 16);
            width = 1ll + box[2] - box[0];
            height = 1ll + box[3] - box[1];
        } else if (attribute == "channels" && type == "chlist" && size <= kMaxChannelListBytes) {
            // name\0, pixel type (int32: 0 uint, 1 half, 2 float), pLinear, 3 reserved, x and y sampling.
            std::vector<char> list(static_cast<std::size_t>(size));
            in.read(list.data(), size);
            for (std::size_t k = 0; k < list.size() && list[k] != '\0';) {
                const auto end = std::find(list.begin() + std::ptrdiff_t(k), list.end(), '\0');
                k = std::size_t(end - list.begin()) + 1;
                if (list.size() - std::min(k, list.size()) < 16) throw corrupt("corrupt OpenEXR channel list");
                std::int32_t pixel_type;
                std::memcpy(&pixel_type, &list[k], 4);
                bytes_per_pixel += pixel_type == 1 ? 2 : 4;
                k += 16;
            }
        } else if (attribute == "channels") {
            throw corrupt("OpenEXR channel list of " + std::to_string(size) + " bytes (limit 1 MiB)");
        } else if (attribute == "tiles" && type == "tiledesc" && size == 9) {
            in.read(reinterpret_cast<char*>(tile), 8);
            in.seekg(1, std::ios::cur);
        } else {
            in.seekg(size, std::ios::cur);
        }
    }
    if (!in) throw corrupt("truncated or corrupt OpenEXR header");
    if (width == -1 || bytes_per_pixel == 0) throw corrupt("OpenEXR header without a data window or channels");
    if (width <= 0 || height <= 0 || width > kMaxImageWidth || height > kMaxImageHeight)
        throw corrupt("image size " + std::to_string(width) + "x" + std::to_string(height) +
                      " is outside the accepted 1x1.." + std::to_string(kMaxImageWidth) + "x" +
                      std::to_string(kMaxImageHeight));
    if (check_size) check_size(int(width), int(height));
    const bool tiled = tile[0] != 0 || tile[1] != 0;
    if (tiled && (tile[0] == 0 || tile[1] == 0)) throw corrupt("OpenEXR tile of zero size");
    const std::uint64_t chunk_pixels = tiled ? std::uint64_t(tile[0]) * tile[1] : 256ull * std::uint64_t(width);
    if (chunk_pixels > kMaxChunkBytes || chunk_pixels * bytes_per_pixel > kMaxChunkBytes)
        throw corrupt("OpenEXR chunks (tiles or line blocks) over 1 GiB");
    // A tile may overhang a small picture (64x64 tiles over a 16x8 picture are common), but OpenEXR
    // allocates whole tiles, and a flipped bit in a tile size makes one of hundreds of MB.
    if (tiled && chunk_pixels > std::max<std::uint64_t>(std::uint64_t(width) * std::uint64_t(height), kMaxTileOverhang))
        throw corrupt("OpenEXR tiles of " + std::to_string(tile[0]) + "x" + std::to_string(tile[1]) +
                      " texels, larger than the " + std::to_string(width) + "x" + std::to_string(height) +
                      " picture and than 1 M texels");
    if (tiled) {
        const std::uint64_t tiles =
            ((std::uint64_t(width) + tile[0] - 1) / tile[0]) * ((std::uint64_t(height) + tile[1] - 1) / tile[1]);
        if (8 * tiles > file_size)
            throw corrupt("the offset table of " + std::to_string(tiles) + " tiles is larger than the file");
    }
}

}  // namespace

ExrContents read_exr(const std::filesystem::path& path, const ImageSizeCheck& check_size) {
    const std::string name = path.string();
    std::error_code ec;  // a FIFO or device would block or never end: regular files only
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(name + ": file not found");
    check_exr_header(path, name, check_size);
    try {
        Imf::InputFile file(name.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        const long long width = static_cast<long long>(window.max.x) - window.min.x + 1;
        const long long height = static_cast<long long>(window.max.y) - window.min.y + 1;
        if (width <= 0 || height <= 0 || width > kMaxImageWidth || height > kMaxImageHeight)
            throw InputError(name + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                             " is outside the accepted 1x1.." + std::to_string(kMaxImageWidth) + "x" +
                             std::to_string(kMaxImageHeight));
        const Imf::ChannelList& channels = file.header().channels();
        for (const char* c : {"R", "G", "B"})
            if (!channels.findChannel(c))
                throw InputError(name + ": no " + std::string(c) + " channel (RGB or RGBA expected)");

        ExrContents result;
        result.had_alpha = channels.findChannel("A") != nullptr;
        result.image = Image(int(width), int(height), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        float* base = &result.image.pixels[0].x;
        Imf::FrameBuffer frame;
        const size_t xs = sizeof(glm::vec4), ys = xs * size_t(width);
        const char* names[4] = {"R", "G", "B", "A"};
        for (int c = 0; c < 4; ++c)
            frame.insert(names[c], Imf::Slice::Make(Imf::FLOAT, base + c, window, xs, ys, 1, 1, c == 3 ? 1.0 : 0.0));
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
        return result;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(name + ": not a readable OpenEXR file (" + std::string(e.what()) + ")");
    }
}

void write_exr(const std::filesystem::path& path, const Image& image) {
    write_atomically(path, [&](const std::filesystem::path& temporary) {
        try {
            Imf::Header header(image.width, image.height);
            header.compression() = Imf::ZIP_COMPRESSION;
            const char* names[4] = {"R", "G", "B", "A"};
            for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
            Imf::OutputFile file(temporary.string().c_str(), header);
            Imf::FrameBuffer frame;
            const char* base = reinterpret_cast<const char*>(image.pixels.data());
            for (int c = 0; c < 4; ++c)
                frame.insert(names[c], Imf::Slice(Imf::FLOAT, const_cast<char*>(base + c * sizeof(float)),
                                                  sizeof(glm::vec4), sizeof(glm::vec4) * size_t(image.width)));
            file.setFrameBuffer(frame);
            file.writePixels(image.height);
        } catch (const std::exception& e) {
            throw InputError(path.string() + ": cannot write EXR (" + std::string(e.what()) + ")");
        }
    });
}

void write_png(const std::filesystem::path& path, const Image8& image) {
    write_atomically(path, [&](const std::filesystem::path& temporary) {
        if (!stbi_write_png(temporary.string().c_str(), image.width, image.height, 4, image.rgba.data(),
                            image.width * 4))
            throw InputError(path.string() + ": cannot write PNG (check the folder exists and is writable)");
    });
}

Image8 read_png(const std::filesystem::path& path) {
    int w = 0, h = 0, n = 0;
    stbi_uc* data = stbi_load(path.string().c_str(), &w, &h, &n, 4);
    if (!data) throw InputError(path.string() + ": cannot read image (" + std::string(stbi_failure_reason()) + ")");
    Image8 image(w, h);
    std::copy(data, data + size_t(w) * size_t(h) * 4, image.rgba.begin());
    stbi_image_free(data);
    return image;
}

float srgb_encode(float linear) {
    linear = std::clamp(linear, 0.0f, 1.0f);
    return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

Image8 tonemap_to_srgb8(const Image& linear, float exposure_stops, ToneMap op) {
    Image8 out(linear.width, linear.height);
    const float scale = std::exp2(exposure_stops);
    for (size_t i = 0; i < linear.pixels.size(); ++i) {
        const glm::vec4 p = linear.pixels[i];
        glm::vec3 exposed;
        for (int c = 0; c < 3; ++c) exposed[c] = std::isfinite(p[c]) ? p[c] * scale : 0.0f;
        const glm::vec3 display = tone_map(op, exposed);
        for (int c = 0; c < 3; ++c) out.rgba[i * 4 + c] = std::uint8_t(std::lround(255.0f * srgb_encode(display[c])));
        out.rgba[i * 4 + 3] = std::uint8_t(std::lround(255.0f * std::clamp(p.a, 0.0f, 1.0f)));
    }
    return out;
}

}  // namespace envshadow
