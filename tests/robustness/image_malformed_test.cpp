// EXR and Radiance HDR inputs: the small valid files the tests write load with their values; every
// truncation and random bit flips either load soundly or fail with one line naming the file; the
// run-length scanline cut short that hangs stb_image (CVE-2021-42715) fails at once; absurd sizes
// fail before any allocation.
#include <sys/resource.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "core/image.h"
#include "env/environment.h"
#include "robustness_support.h"
#include "sample_inputs.h"

namespace envshadow {
namespace {

namespace fs = std::filesystem;
using test::fresh_folder;
using test::loads_or_fails_cleanly;
using test::write_text;

std::vector<glm::vec3> sample_texels(int width, int height) {
    std::vector<glm::vec3> texels;
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) texels.push_back(test::sample_radiance(i, j, width, height));
    return texels;
}

void expect_sound_image(const Image& image) {
    ASSERT_GE(image.width, 1);
    ASSERT_GE(image.height, 1);
    ASSERT_LE(image.width, kMaxImageWidth);
    ASSERT_LE(image.height, kMaxImageHeight);
    ASSERT_EQ(image.pixels.size(), std::size_t(image.width) * std::size_t(image.height));
}

void expect_input_error(const fs::path& file, const std::function<void()>& load, const std::string& expected) {
    try {
        load();
        ADD_FAILURE() << file << " loaded";
    } catch (const InputError& e) {
        EXPECT_TRUE(test::is_one_line_naming(e.what(), file));
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
}

// --- Radiance HDR -------------------------------------------------------------------------------

TEST(RobustHdr, RunLengthAndFlatFilesHoldTheirTexelsToRgbePrecision) {
    const fs::path dir = fresh_folder();
    const int width = 300, height = 150;  // wider than one run (127) and not a multiple of it
    const std::vector<glm::vec3> texels = sample_texels(width, height);
    for (const bool run_length : {true, false}) {
        const fs::path file = dir / (run_length ? "rle.hdr" : "flat.hdr");
        test::write_bytes(file, test::hdr_bytes(width, height, texels, run_length));
        const Image image = read_radiance_hdr(file);
        ASSERT_EQ(image.width, width);
        ASSERT_EQ(image.height, height);
        for (std::size_t t = 0; t < texels.size(); ++t) {
            // An 8-bit mantissa under a shared exponent: each channel within 1/128 of the largest.
            const float step = std::max({texels[t].r, texels[t].g, texels[t].b}) / 128.0f;
            for (int c = 0; c < 3; ++c) ASSERT_NEAR(image.pixels[t][c], texels[t][c], step) << "texel " << t;
            ASSERT_EQ(image.pixels[t].a, 1.0f);
        }
    }
}

TEST(RobustHdr, ZeroAndCrlfHeadersRead) {
    const fs::path dir = fresh_folder();
    std::vector<std::uint8_t> bytes = test::hdr_bytes(8, 1, std::vector<glm::vec3>(8, glm::vec3(0.0f)), false);
    test::write_bytes(dir / "black.hdr", bytes);
    const Image black = read_radiance_hdr(dir / "black.hdr");
    for (const glm::vec4& p : black.pixels) EXPECT_EQ(p, glm::vec4(0, 0, 0, 1));

    std::string header = "#?RGBE\r\nFORMAT=32-bit_rle_rgbe\r\n\r\n-Y 1 +X 2 \r\n";
    std::vector<std::uint8_t> crlf(header.begin(), header.end());
    crlf.insert(crlf.end(), {128, 64, 32, 129, 0, 0, 0, 0});  // (1, 0.5, 0.25), then black
    test::write_bytes(dir / "crlf.hdr", crlf);
    const Image image = read_radiance_hdr(dir / "crlf.hdr");
    EXPECT_EQ(image.pixels[0], glm::vec4(1.0f, 0.5f, 0.25f, 1.0f));
    EXPECT_EQ(image.pixels[1], glm::vec4(0, 0, 0, 1));
}

TEST(RobustHdr, EveryTruncatedFileIsRefused) {
    const fs::path dir = fresh_folder();
    for (const bool run_length : {true, false}) {
        const auto whole = test::hdr_bytes(64, 32, sample_texels(64, 32), run_length);
        const fs::path file = dir / "cut.hdr";
        for (const std::size_t n : test::truncation_lengths(whole.size(), 200, 400)) {
            test::write_bytes(file, std::vector<std::uint8_t>(whole.begin(), whole.begin() + std::ptrdiff_t(n)));
            EXPECT_FALSE(loads_or_fails_cleanly(
                file, [&] { read_radiance_hdr(file); }, std::to_string(n)))
                << "cut to " << n << " of " << whole.size() << " bytes, " << (run_length ? "RLE" : "flat");
        }
    }
}

TEST(RobustHdr, BitFlippedFilesLoadSoundlyOrAreRefused) {
    const fs::path dir = fresh_folder();
    const fs::path file = dir / "flipped.hdr";
    int index = 0;
    for (const bool run_length : {true, false})
        for (const auto& bytes :
             test::bit_flipped(test::hdr_bytes(32, 16, sample_texels(32, 16), run_length), 800, run_length ? 11 : 12)) {
            test::write_bytes(file, bytes);
            const std::string what = "mutant " + std::to_string(index++);
            loads_or_fails_cleanly(
                file, [&] { expect_sound_image(read_radiance_hdr(file)); }, what);
        }
}

TEST(RobustHdr, ARunLengthScanlineCutShortFailsAtOnce) {
    // stb_image 2.27 reads the missing counts as 0 and loops for ever (CVE-2021-42715).
    const fs::path dir = fresh_folder();
    const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 16\n";
    std::vector<std::uint8_t> bytes(header.begin(), header.end());
    bytes.insert(bytes.end(), {2, 2, 0, 16});  // scanline 0: four channels, each 16 literal bytes
    for (int channel = 0; channel < 4; ++channel) {
        bytes.push_back(16);
        bytes.insert(bytes.end(), 16, std::uint8_t(100 + channel));
    }
    const std::vector<std::uint8_t> first_scanline = bytes;
    bytes.insert(bytes.end(), {2, 2, 0, 16, 128 + 16, 100});  // scanline 1: one channel of four
    test::write_bytes(dir / "cut.hdr", bytes);
    const auto start = std::chrono::steady_clock::now();
    expect_input_error(
        dir / "cut.hdr", [&] { read_radiance_hdr(dir / "cut.hdr"); }, "truncated in scanline 1");
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));

    // A zero count inside a scanline is refused too (it would never advance).
    bytes = first_scanline;
    bytes.insert(bytes.end(), {2, 2, 0, 16, 0, 0, 0, 0, 0, 0, 0, 0});
    test::write_bytes(dir / "zero.hdr", bytes);
    expect_input_error(
        dir / "zero.hdr", [&] { read_radiance_hdr(dir / "zero.hdr"); }, "bad run length 0");
}

TEST(RobustHdr, HeadersThatCannotBeReadAreRefused) {
    const fs::path dir = fresh_folder();
    const struct {
        const char* name;
        std::string text;
        const char* expected;
    } cases[] = {
        {"no_signature", "RADIANCE\n\n-Y 1 +X 1\n\1\1\1\1", "no #?RADIANCE signature"},
        {"xyze", "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n\1\1\1\1", "32-bit_rle_xyze"},
        {"flipped", "#?RADIANCE\n\n+Y 1 +X 1\n\1\1\1\1", "is not '-Y height +X width'"},
        {"overflow", "#?RADIANCE\n\n-Y 99999999999999999999999 +X 1\n", "is not '-Y height +X width'"},
        {"negative", "#?RADIANCE\n\n-Y -4 +X 8\n", "outside 1x1"},
        {"huge", "#?RADIANCE\n\n-Y 8192 +X 16385\n", "outside 1x1"},
        {"no_end", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n", "header ends before the resolution line"},
        {"endless", "#?RADIANCE\n" + std::string(70000, '#'), "header longer than 64 KiB"},
        // 16384 x 8192 needs 8.5 MB even run-length encoded: refused before 2 GiB are allocated.
        {"tiny", "#?RADIANCE\n\n-Y 8192 +X 16384\n" + std::string("\2\2\x40\0", 4),
         "file too short for 16384x8192 texels"},
    };
    for (const auto& c : cases) {
        const fs::path file = dir / (std::string(c.name) + ".hdr");
        write_text(file, c.text);
        expect_input_error(
            file, [&] { read_radiance_hdr(file); }, c.expected);
    }
    expect_input_error(
        dir / "absent.hdr", [&] { read_radiance_hdr(dir / "absent.hdr"); }, "file not found");
    ASSERT_EQ(::mkfifo((dir / "pipe.hdr").c_str(), 0600), 0);
    expect_input_error(
        dir / "pipe.hdr", [&] { read_radiance_hdr(dir / "pipe.hdr"); }, "file not found");
}

// --- OpenEXR ------------------------------------------------------------------------------------

TEST(RobustExr, EveryCompressionAndLayoutReads) {
    const fs::path dir = fresh_folder();
    for (int compression = 0; compression <= 9; ++compression) {
        const fs::path file = dir / ("c" + std::to_string(compression) + ".exr");
        test::write_sample_exr(file, 40, 20, compression, test::ExrLayout::tiled, test::ExrPixels::full_float);
        const ExrContents contents = read_exr(file);
        ASSERT_EQ(contents.image.width, 40);
        ASSERT_EQ(contents.image.height, 20);
        // Lossy compressions (B44 6-7, DWA 8-9) and PXR24 (5, 24-bit floats) are close, the others exact.
        const float tolerance = compression >= 5 ? 0.05f : 0.0f;
        for (int j = 0; j < 20; ++j)
            for (int i = 0; i < 40; ++i) {
                const glm::vec3 expected = test::sample_radiance(i, j, 40, 20);
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(contents.image.at(i, j)[c], expected[c], tolerance * expected[c] + 1e-6f)
                        << "compression " << compression << " texel " << i << "," << j;
            }
    }
}

TEST(RobustExr, EveryTruncatedFileIsRefused) {
    const fs::path dir = fresh_folder();
    const fs::path whole_file = dir / "whole.exr";
    for (const int compression : {0, 3, 4}) {  // none, ZIP, PIZ
        test::write_sample_exr(whole_file, 64, 32, compression);
        const auto whole = test::read_bytes(whole_file);
        const fs::path file = dir / "cut.exr";
        for (const std::size_t n : test::truncation_lengths(whole.size(), 400, 200)) {
            test::write_bytes(file, std::vector<std::uint8_t>(whole.begin(), whole.begin() + std::ptrdiff_t(n)));
            EXPECT_FALSE(loads_or_fails_cleanly(
                file, [&] { read_exr(file); }, std::to_string(n)))
                << "compression " << compression << " cut to " << n << " of " << whole.size() << " bytes";
        }
    }
}

TEST(RobustExr, BitFlippedFilesLoadSoundlyOrAreRefused) {
    const fs::path dir = fresh_folder();
    const fs::path file = dir / "flipped.exr";
    int index = 0;
    for (const int compression : {0, 1, 3, 4}) {
        test::write_sample_exr(dir / "whole.exr", 32, 16, compression);
        for (const auto& bytes : test::bit_flipped(test::read_bytes(dir / "whole.exr"), 300, 100 + compression)) {
            test::write_bytes(file, bytes);
            const std::string what = "mutant " + std::to_string(index++);
            loads_or_fails_cleanly(
                file, [&] { expect_sound_image(read_exr(file).image); }, what);
        }
    }
}

TEST(RobustExr, TheBlenderPhotographsRead) {
    // docs/DESIGN.md §7: eight 1024x512 maps.
    int count = 0;
    for (const auto& entry : fs::directory_iterator("/usr/share/blender/datafiles/studiolights/world")) {
        if (entry.path().extension() != ".exr") continue;
        const ExrContents contents = read_exr(entry.path());
        EXPECT_EQ(contents.image.width, 1024) << entry.path();
        EXPECT_EQ(contents.image.height, 512) << entry.path();
        ++count;
    }
    EXPECT_EQ(count, 8);
}

// The offset of a header attribute's int32 size field in an EXR file.
std::size_t attribute_size_at(const std::vector<std::uint8_t>& bytes, const std::string& name_and_type) {
    const auto it = std::search(bytes.begin(), bytes.end(), name_and_type.begin(), name_and_type.end());
    EXPECT_NE(it, bytes.end()) << name_and_type;
    return std::size_t(it - bytes.begin()) + name_and_type.size();
}

TEST(RobustExr, HeaderSizesAreCheckedBeforeOpenExrAllocates) {
    const fs::path dir = fresh_folder();
    test::write_sample_exr(dir / "whole.exr", 16, 8, 0);
    const auto whole = test::read_bytes(dir / "whole.exr");

    // An attribute declaring 2 GB in a file of a few hundred bytes (OpenEXR would allocate it).
    auto bytes = whole;
    const std::size_t channels = attribute_size_at(bytes, std::string("channels\0chlist\0", 16));
    const std::uint32_t huge = 0x7ffffff0u;
    std::memcpy(&bytes[channels], &huge, 4);
    test::write_bytes(dir / "attribute.exr", bytes);
    expect_input_error(
        dir / "attribute.exr", [&] { read_exr(dir / "attribute.exr"); },
        "header attribute 'channels' claims 2147483632 bytes, more than the file holds");

    // A data window of 2^31 - 1 rows (OpenEXR would read a line offset table for them).
    bytes = whole;
    const std::size_t window = attribute_size_at(bytes, std::string("dataWindow\0box2i\0", 17)) + 4;
    const std::int32_t box[4] = {0, 0, 15, 2147483646};
    std::memcpy(&bytes[window], box, 16);
    test::write_bytes(dir / "window.exr", bytes);
    expect_input_error(
        dir / "window.exr", [&] { read_exr(dir / "window.exr"); },
        "image size 16x2147483647 is outside the accepted 1x1..16384x16384");

    // Tiles of 16 x 15.5 million texels (OpenEXR would allocate a 1.5 GB tile buffer).
    test::write_sample_exr(dir / "tiled.exr", 40, 20, 0, test::ExrLayout::tiled);
    bytes = test::read_bytes(dir / "tiled.exr");
    const std::size_t tiles = attribute_size_at(bytes, std::string("tiles\0tiledesc\0", 15)) + 4;
    const std::uint32_t tile_size[2] = {16, 0x00ed105e};
    std::memcpy(&bytes[tiles], tile_size, 8);
    test::write_bytes(dir / "tile.exr", bytes);
    expect_input_error(
        dir / "tile.exr", [&] { read_exr(dir / "tile.exr"); }, "OpenEXR chunks (tiles or line blocks) over 1 GiB");

    // One flipped bit (7 of byte 337 in tests/env_contract's 64x32 file) turns 16x16 tiles into
    // 16 x 8,388,624: under 1 GiB, but 800 MB for OpenEXR to allocate for a 40x20 picture.
    const std::uint32_t long_tile[2] = {16, 0x00800010};
    std::memcpy(&bytes[tiles], long_tile, 8);
    test::write_bytes(dir / "long_tile.exr", bytes);
    expect_input_error(
        dir / "long_tile.exr", [&] { read_exr(dir / "long_tile.exr"); },
        "OpenEXR tiles of 16x8388624 texels, larger than the 40x20 picture and than 1 M texels");
    // Tiles overhanging a small picture (16x16 over 8x4) stay readable.
    test::write_sample_exr(dir / "overhang.exr", 8, 4, 0, test::ExrLayout::tiled);
    EXPECT_EQ(read_exr(dir / "overhang.exr").image.width, 8);
}

// --- Environment maps: the shape is checked before the pixels are allocated ---------------------

// The process's peak resident memory so far, in MiB.
long peak_rss_mib() {
    rusage usage{};
    ::getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss / 1024;
}

// An EXR of a few kilobytes whose header declares `width` x `height` (ZIP, 16 lines a chunk) and
// whose line offset table is whole, every entry pointing at the one real chunk: OpenEXR opens it
// and only fails when it reads the pixels, after read_exr has allocated them.
std::vector<std::uint8_t> exr_declaring(const fs::path& dir, std::int32_t width, std::int32_t height) {
    test::write_sample_exr(dir / "small.exr", 16, 8, 3);  // one ZIP chunk
    const auto small = test::read_bytes(dir / "small.exr");
    std::size_t at = 8;  // magic and version, then "name\0type\0" + int32 size + value, until an empty name
    const auto skip_string = [&] {
        while (small.at(at) != 0) ++at;
        return small.at(at++) == 0 && small.at(at - 2) != 0;
    };
    while (small.at(at) != 0) {
        skip_string();
        skip_string();
        std::int32_t size;
        std::memcpy(&size, &small.at(at), 4);
        at += 4 + std::size_t(size);
    }
    const std::size_t header_end = at + 1, chunks = std::size_t(height + 15) / 16;
    std::vector<std::uint8_t> bytes(small.begin(), small.begin() + std::ptrdiff_t(header_end));
    const std::size_t window = attribute_size_at(bytes, std::string("dataWindow\0box2i\0", 17)) + 4;
    const std::int32_t box[4] = {0, 0, width - 1, height - 1};
    std::memcpy(&bytes[window], box, 16);
    const std::uint64_t chunk_at = header_end + 8 * chunks;
    for (std::size_t k = 0; k < chunks; ++k)
        bytes.insert(bytes.end(), reinterpret_cast<const std::uint8_t*>(&chunk_at),
                     reinterpret_cast<const std::uint8_t*>(&chunk_at) + 8);
    bytes.insert(bytes.end(), small.begin() + std::ptrdiff_t(header_end + 8), small.end());
    return bytes;
}

// Files whose headers declare a picture within the readers' limits (16384 x 16384) but no lat-long
// map: read in full one would take 4 GiB. load_environment must refuse them for their shape, naming
// the file, before the readers allocate anything that size (the resident peak must not grow by
// more than a few hundred MiB).
TEST(RobustEnvironment, AWronglyShapedMapIsRefusedBeforeItsPixelsAreAllocated) {
    const fs::path dir = fresh_folder();
    const struct {
        const char* name;
        std::int32_t width, height;
        const char* expected;
    } exr_cases[] = {
        {"tall", 16384, 16383, "map size 16384x16383 is outside the accepted 2x1..16384x8192"},
        {"square", 16384, 16384, "map size 16384x16384 is outside the accepted 2x1..16384x8192"},
        {"narrow", 16383, 8192, "map size 16383x8192 is not a lat-long map"},
    };
    for (const auto& c : exr_cases) {
        const fs::path file = dir / (std::string(c.name) + ".exr");
        test::write_bytes(file, exr_declaring(dir, c.width, c.height));
        ASSERT_LT(fs::file_size(file), 16u * 1024);
        const long before = peak_rss_mib();
        expect_input_error(
            file, [&] { load_environment(file.string()); }, c.expected);
        EXPECT_LT(peak_rss_mib() - before, 256) << c.name << ": MiB allocated before the shape was checked";
    }

    // Radiance HDR: the shape is checked before the length of the file (which bounds the picture
    // only to what run-length encoding can reach: ~250 bytes of texels per byte of file).
    write_text(dir / "tall.hdr", "#?RADIANCE\n\n-Y 16383 +X 16384\n" + std::string("\2\2\x40\0", 4));
    expect_input_error(
        dir / "tall.hdr", [&] { load_environment((dir / "tall.hdr").string()); },
        "map size 16384x16383 is outside the accepted 2x1..16384x8192");

    // The readers alone still take any picture within their limits (compare reads such EXRs).
    expect_input_error(
        dir / "tall.hdr", [&] { read_radiance_hdr(dir / "tall.hdr"); }, "file too short");
}

TEST(RobustExr, NonFiniteAndNegativeTexelsAreReadAsTheyAre) {
    // read_exr hands the values on; what to do with them is the environment loader's decision.
    const fs::path dir = fresh_folder();
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    test::write_exr_texels(dir / "odd.exr", 2, 1, {{nan, -0.003f, 1.0f}, {inf, -inf, 0.0f}});
    const Image image = read_exr(dir / "odd.exr").image;
    EXPECT_TRUE(std::isnan(image.pixels[0].r));
    EXPECT_EQ(image.pixels[0].g, -0.003f);
    EXPECT_EQ(image.pixels[1].r, inf);
    EXPECT_EQ(image.pixels[1].g, -inf);
}

TEST(RobustExr, SpecialFilesAreRefused) {
    const fs::path dir = fresh_folder();
    ASSERT_EQ(::mkfifo((dir / "pipe.exr").c_str(), 0600), 0);
    expect_input_error(
        dir / "pipe.exr", [&] { read_exr(dir / "pipe.exr"); }, "");
    fs::create_directory(dir / "folder.exr");
    expect_input_error(
        dir / "folder.exr", [&] { read_exr(dir / "folder.exr"); }, "");
    expect_input_error(
        "/dev/zero", [&] { read_exr("/dev/zero"); }, "");
}

}  // namespace
}  // namespace envshadow
