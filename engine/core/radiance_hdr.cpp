// Radiance RGBE (.hdr) reader: header lines up to an empty one, the resolution line "-Y H +X W",
// then H scanlines, each run-length encoded (2, 2, W >> 8, W & 255, then four channels of runs and
// literals) or flat (W RGBE quadruples). Written here rather than taken from stb_image 2.27, whose
// decoder loops for ever on a run-length scanline cut short (CVE-2021-42715); every count and length
// is checked against what remains of the file.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/image.h"

namespace envshadow {
namespace {

constexpr std::size_t kMaxHeaderBytes = 64 * 1024;

class RgbeReader {
public:
    RgbeReader(std::string name, std::vector<std::uint8_t> bytes) : name_(std::move(name)), bytes_(std::move(bytes)) {}

    Image read() {
        const auto [width, height] = header();
        // The smallest possible scanline: flat, or four channels of runs of at most 127 texels.
        const std::size_t rle_min = 4 + 4 * 2 * ((std::size_t(width) + 126) / 127);
        const std::size_t flat = 4 * std::size_t(width);
        const std::size_t shortest = width >= 8 && width < 32768 ? std::min(rle_min, flat) : flat;
        if (shortest * std::size_t(height) > bytes_.size() - at_)
            fail("file too short for " + std::to_string(width) + "x" + std::to_string(height) + " texels (" +
                 std::to_string(bytes_.size()) + " bytes)");

        Image image(width, height, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        std::vector<std::uint8_t> scanline(std::size_t(width) * 4);
        for (int j = 0; j < height; ++j) {
            read_scanline(scanline, width, j);
            for (int i = 0; i < width; ++i) {
                const std::uint8_t* rgbe = &scanline[std::size_t(i) * 4];
                glm::vec4& texel = image.at(i, j);
                if (rgbe[3] == 0) continue;  // exponent 0 is black
                // As stb_image and Radiance's colr_color: mantissa * 2^(e - 136), no half-step offset.
                const float scale = std::ldexp(1.0f, int(rgbe[3]) - (128 + 8));
                texel = glm::vec4(rgbe[0] * scale, rgbe[1] * scale, rgbe[2] * scale, 1.0f);
            }
        }
        return image;
    }

private:
    [[noreturn]] void fail(const std::string& reason) const {
        throw InputError(name_ + ": not a readable Radiance HDR file (" + reason + ")");
    }

    std::uint8_t byte(int j) {
        if (at_ >= bytes_.size()) fail("truncated in scanline " + std::to_string(j));
        return bytes_[at_++];
    }

    std::string line() {
        std::string text;
        while (true) {
            if (at_ >= bytes_.size()) fail("header ends before the resolution line");
            if (at_ >= kMaxHeaderBytes) fail("header longer than 64 KiB");
            const char c = char(bytes_[at_++]);
            if (c == '\n') {
                if (!text.empty() && text.back() == '\r') text.pop_back();  // CRLF line ends
                return text;
            }
            text += c;
        }
    }

    // "-Y H +X W" (rows from the top, texels from the left: the only layout read), numbers checked
    // for overflow.
    static bool parse_resolution(const std::string& text, long long& height, long long& width) {
        const char* p = text.data();
        const char* end = p + text.size();
        auto literal = [&](const char* expected) {
            const std::size_t n = std::strlen(expected);
            if (std::size_t(end - p) < n || std::memcmp(p, expected, n) != 0) return false;
            p += n;
            return true;
        };
        auto number = [&](long long& value) {
            const auto [next, error] = std::from_chars(p, end, value);
            if (error != std::errc()) return false;
            p = next;
            return true;
        };
        if (!literal("-Y ") || !number(height) || !literal(" +X ") || !number(width)) return false;
        return std::all_of(p, end, [](char c) { return c == ' ' || c == '\t'; });
    }

    std::pair<int, int> header() {
        const std::string magic = line();
        if (magic.rfind("#?", 0) != 0) fail("no #?RADIANCE signature");
        while (true) {
            const std::string entry = line();
            if (entry.empty()) break;
            if (entry.rfind("FORMAT=", 0) == 0 && entry != "FORMAT=32-bit_rle_rgbe")
                fail("pixel format " + entry.substr(7) + " (only 32-bit_rle_rgbe is read)");
        }
        const std::string resolution = line();
        long long height = 0, width = 0;
        if (!parse_resolution(resolution, height, width))
            fail("resolution line '" + resolution.substr(0, 40) + "' is not '-Y height +X width'");
        if (width < 1 || height < 1 || width > kMaxImageWidth || height > kMaxImageHeight)
            fail("size " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1x1.." +
                 std::to_string(kMaxImageWidth) + "x" + std::to_string(kMaxImageHeight));
        return {int(width), int(height)};
    }

    void read_scanline(std::vector<std::uint8_t>& out, int width, int j) {
        const bool run_length = width >= 8 && width < 32768 && bytes_.size() - at_ >= 4 && bytes_[at_] == 2 &&
                                bytes_[at_ + 1] == 2 && (bytes_[at_ + 2] & 0x80) == 0;
        if (!run_length) {
            for (std::uint8_t& b : out) b = byte(j);
            return;
        }
        at_ += 2;
        const int high = byte(j);
        const int length = high << 8 | byte(j);
        if (length != width)
            fail("scanline " + std::to_string(j) + " says " + std::to_string(length) + " texels, not " +
                 std::to_string(width));
        for (int channel = 0; channel < 4; ++channel) {
            int i = 0;
            while (i < width) {
                int count = byte(j);
                const bool run = count > 128;
                if (run) count -= 128;
                if (count == 0 || count > width - i)
                    fail("bad run length " + std::to_string(count) + " in scanline " + std::to_string(j));
                if (run) {
                    const std::uint8_t value = byte(j);
                    for (int k = 0; k < count; ++k) out[std::size_t(i++) * 4 + std::size_t(channel)] = value;
                } else {
                    for (int k = 0; k < count; ++k) out[std::size_t(i++) * 4 + std::size_t(channel)] = byte(j);
                }
            }
        }
    }

    std::string name_;
    std::vector<std::uint8_t> bytes_;
    std::size_t at_ = 0;
};

}  // namespace

Image read_radiance_hdr(const std::filesystem::path& path) {
    const std::string name = path.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(name + ": file not found");
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    // The largest map, flat: 4 bytes a texel, plus a header.
    if (ec || size > 4ull * kMaxImageWidth * kMaxImageHeight + kMaxHeaderBytes)
        throw InputError(name + ": cannot read the file size, or the file is too large");
    std::vector<std::uint8_t> bytes(size);
    std::ifstream in(path, std::ios::binary);
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size)))
        throw InputError(name + ": cannot read the file");
    return RgbeReader(name, std::move(bytes)).read();
}

}  // namespace envshadow
