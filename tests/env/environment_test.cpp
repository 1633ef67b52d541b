#include "env/environment.h"

#include <Imath/half.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfTileDescription.h>
#include <ImfTiledOutputFile.h>
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <glm/vec4.hpp>
#include <numbers>

#include "core/error.h"
#include "env/latlong.h"
#include "env_test_data.h"

namespace envshadow {
namespace {

using Texel = std::function<glm::vec4(int i, int j)>;

struct ExrLayout {
    Imf::PixelType type = Imf::FLOAT;
    Imf::Compression compression = Imf::ZIP_COMPRESSION;
    bool tiled = false;
    bool alpha = false;
};

void write_exr_file(const std::filesystem::path& path, int width, int height, const Texel& texel, ExrLayout layout) {
    std::vector<glm::vec4> pixels(size_t(width) * size_t(height));
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) pixels[size_t(j) * size_t(width) + size_t(i)] = texel(i, j);
    Imf::Header header(width, height);
    header.compression() = layout.compression;
    const char* names[4] = {"R", "G", "B", "A"};
    const int channels = layout.alpha ? 4 : 3;
    for (int c = 0; c < channels; ++c) header.channels().insert(names[c], Imf::Channel(layout.type));
    // Writing needs slices of the file's type: half channels are written from a half copy.
    std::vector<half> halves(pixels.size() * 4);
    for (size_t k = 0; k < pixels.size(); ++k)
        for (int c = 0; c < 4; ++c) halves[4 * k + size_t(c)] = half(pixels[k][c]);
    Imf::FrameBuffer frame;
    for (int c = 0; c < channels; ++c) {
        if (layout.type == Imf::HALF)
            frame.insert(names[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(&halves[size_t(c)]), 4 * sizeof(half),
                                              4 * sizeof(half) * size_t(width)));
        else
            frame.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(&pixels[0][c]), sizeof(glm::vec4),
                                              sizeof(glm::vec4) * size_t(width)));
    }
    if (layout.tiled) {
        header.setTileDescription(Imf::TileDescription(16, 16, Imf::ONE_LEVEL));
        Imf::TiledOutputFile file(path.string().c_str(), header);
        file.setFrameBuffer(frame);
        file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
    } else {
        Imf::OutputFile file(path.string().c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(height);
    }
}

glm::vec4 smooth_texel(int i, int j) {
    return {0.5f + 0.01f * i, 0.25f + 0.02f * j, 1.0f + 0.001f * (i * j), 1.0f};
}

std::string read_bytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}
void write_bytes(const std::filesystem::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

// The load either fails cleanly or gives a valid map: never a crash, never bad texels.
void expect_input_error_or_valid_map(const std::filesystem::path& path) {
    try {
        const EnvironmentMap map = load_environment(path.string(), {true});
        EXPECT_EQ(map.width, 2 * map.height);
        for (const glm::vec3& t : map.texels)
            for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(t[c]) && t[c] >= 0.0f);
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(path.filename().string()), std::string::npos) << e.what();
    }
}

void expect_input_error_naming(const std::string& spec, const std::string& fragment,
                               const EnvironmentLoadOptions& options = {}) {
    try {
        load_environment(spec, options);
        FAIL() << spec << ": no error";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(fragment), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
    }
}

TEST(Environment, LoadsTheBlenderPhotographsWithoutNegativeOrInvalidTexels) {
    long long negatives = 0;
    for (const std::string& name : test::kWorldNames) {
        EnvironmentLoadReport report;
        const EnvironmentMap map = load_environment(test::world_path(name), {}, &report);
        EXPECT_EQ(map.width, 1024) << name;
        EXPECT_EQ(map.height, 512) << name;
        EXPECT_EQ(report.invalid_clamped, 0) << name;
        negatives += report.negative_clamped;
        for (const glm::vec3& t : map.texels)
            for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(t[c]) && t[c] >= 0.0f) << name;
    }
    EXPECT_GT(negatives, 0);  // blender-data's maps carry small negative texels (about -0.003)
}

TEST(Environment, ReadsEveryExrLayout) {
    const auto dir = test::scratch_folder();
    int index = 0;
    for (Imf::PixelType type : {Imf::HALF, Imf::FLOAT})
        for (bool tiled : {false, true})
            for (bool alpha : {false, true})
                for (Imf::Compression compression :
                     {Imf::NO_COMPRESSION, Imf::RLE_COMPRESSION, Imf::ZIPS_COMPRESSION, Imf::ZIP_COMPRESSION,
                      Imf::PIZ_COMPRESSION, Imf::PXR24_COMPRESSION, Imf::B44_COMPRESSION, Imf::B44A_COMPRESSION,
                      Imf::DWAA_COMPRESSION, Imf::DWAB_COMPRESSION}) {
                    const auto path = dir / ("layout" + std::to_string(index++) + ".exr");
                    write_exr_file(path, 40, 20, smooth_texel, {type, compression, tiled, alpha});
                    const EnvironmentMap map = load_environment(path.string());
                    ASSERT_EQ(map.width, 40);
                    ASSERT_EQ(map.height, 20);
                    // Lossless layouts give the values back (to half precision); B44 and DWA are lossy.
                    const bool lossy = compression == Imf::B44_COMPRESSION || compression == Imf::B44A_COMPRESSION ||
                                       compression == Imf::DWAA_COMPRESSION || compression == Imf::DWAB_COMPRESSION ||
                                       (compression == Imf::PXR24_COMPRESSION && type == Imf::FLOAT);
                    const float tolerance = lossy ? 0.02f : (type == Imf::HALF ? 2e-3f : 1e-6f);
                    for (int j = 0; j < 20; ++j)
                        for (int i = 0; i < 40; ++i)
                            for (int c = 0; c < 3; ++c)
                                ASSERT_NEAR(map.at(i, j)[c], smooth_texel(i, j)[c], tolerance * smooth_texel(i, j)[c])
                                    << path << " texel " << i << "," << j;
                }
}

TEST(Environment, ReadsRadianceHdr) {
    const auto path = test::scratch_folder() / "map.hdr";
    std::vector<float> rgb;
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 32; ++i)
            for (int c = 0; c < 3; ++c) rgb.push_back(smooth_texel(i, j)[c] * 100.0f);
    ASSERT_TRUE(stbi_write_hdr(path.string().c_str(), 32, 16, 3, rgb.data()));
    const EnvironmentMap map = load_environment(path.string());
    ASSERT_EQ(map.width, 32);
    ASSERT_EQ(map.height, 16);
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 32; ++i)
            for (int c = 0; c < 3; ++c)  // RGBE keeps 8 bits of mantissa under a shared exponent
                ASSERT_NEAR(map.at(i, j)[c], 100.0f * smooth_texel(i, j)[c], 0.01f * 100.0f * 1.5f);
}

TEST(Environment, RejectsMapsThatAreNotLatLong) {
    const auto dir = test::scratch_folder();
    write_exr_file(dir / "square.exr", 32, 32, smooth_texel, {});
    expect_input_error_naming((dir / "square.exr").string(), "width must be twice the height");
    std::vector<float> rgb(30 * 20 * 3, 1.0f);
    ASSERT_TRUE(stbi_write_hdr((dir / "wide.hdr").string().c_str(), 30, 20, 3, rgb.data()));
    expect_input_error_naming((dir / "wide.hdr").string(), "width must be twice the height");
}

TEST(Environment, RejectsAbsurdSizesBeforeReadingPixels) {
    const auto path = test::scratch_folder() / "huge.exr";
    write_exr_file(path, 64, 32, smooth_texel, {});
    // Claim a 32768 x 16384 data window in the header (box2i: xMin, yMin, xMax, yMax).
    std::string bytes = read_bytes(path);
    const size_t at = bytes.find(std::string("dataWindow\0box2i\0", 17));
    ASSERT_NE(at, std::string::npos);
    const size_t box = at + 17 + 4;  // after the name, the type and the attribute size
    const std::int32_t xmax = 32767, ymax = 16383;
    std::memcpy(&bytes[box + 8], &xmax, 4);
    std::memcpy(&bytes[box + 12], &ymax, 4);
    write_bytes(path, bytes);
    expect_input_error_naming(path.string(), "huge.exr");
}

TEST(Environment, CorruptFilesGiveOneLineErrorsNamingTheFile) {
    const auto dir = test::scratch_folder();
    const auto valid = dir / "valid.exr";
    write_exr_file(valid, 128, 64, smooth_texel, {Imf::FLOAT, Imf::ZIP_COMPRESSION, false, false});
    const std::string bytes = read_bytes(valid);

    write_bytes(dir / "truncated.exr", bytes.substr(0, bytes.size() / 2));
    expect_input_error_naming((dir / "truncated.exr").string(), "truncated.exr");

    std::string flipped = bytes;
    flipped[0] = char(flipped[0] ^ 0x40);  // the magic number
    write_bytes(dir / "magic.exr", flipped);
    expect_input_error_naming((dir / "magic.exr").string(), "not an OpenEXR or Radiance HDR file");

    flipped = bytes;
    for (size_t k = bytes.size() * 3 / 4; k < bytes.size() * 3 / 4 + 16; ++k) flipped[k] = char(flipped[k] ^ 0xA5);
    write_bytes(dir / "zip_data.exr", flipped);  // zlib notices damaged compressed data
    expect_input_error_naming((dir / "zip_data.exr").string(), "zip_data.exr");

    write_bytes(dir / "text.exr", "not an image at all");
    expect_input_error_naming((dir / "text.exr").string(), "not an OpenEXR or Radiance HDR file");
    expect_input_error_naming((dir / "missing.exr").string(), "missing.exr");
}

TEST(Environment, SingleBitFlipsAnywhereNeverCrash) {
    const auto dir = test::scratch_folder();
    const auto valid = dir / "valid.exr";
    write_exr_file(valid, 64, 32, smooth_texel, {Imf::HALF, Imf::PIZ_COMPRESSION, false, true});
    const std::string bytes = read_bytes(valid);
    for (size_t k = 0; k < bytes.size(); k += std::max<size_t>(1, bytes.size() / 97)) {
        for (int bit : {0, 5}) {
            std::string flipped = bytes;
            flipped[k] = char(flipped[k] ^ (1 << bit));
            const auto path = dir / ("flip_" + std::to_string(k) + "_" + std::to_string(bit) + ".exr");
            write_bytes(path, flipped);
            expect_input_error_or_valid_map(path);
        }
    }
}

TEST(Environment, NanAndInfAreAnErrorUnlessClamped) {
    const auto dir = test::scratch_folder();
    const auto path = dir / "nan.exr";
    auto texel = [](int i, int j) {
        glm::vec4 t = smooth_texel(i, j);
        if (i == 3 && j == 2) t.r = std::numeric_limits<float>::quiet_NaN();
        if (i == 7 && j == 5) t.g = std::numeric_limits<float>::infinity();
        if (i == 9 && j == 1) t.b = -std::numeric_limits<float>::infinity();
        if (i == 1 && j == 1) t.r = -0.003f;
        return t;
    };
    write_exr_file(path, 16, 8, texel, {});
    expect_input_error_naming(path.string(), "NaN");
    EnvironmentLoadReport report;
    const EnvironmentMap map = load_environment(path.string(), {true}, &report);
    EXPECT_EQ(report.invalid_clamped, 3);
    EXPECT_EQ(report.negative_clamped, 1);
    EXPECT_EQ(map.at(3, 2).r, 0.0f);
    EXPECT_EQ(map.at(7, 5).g, 0.0f);
    EXPECT_EQ(map.at(9, 1).b, 0.0f);
    EXPECT_EQ(map.at(1, 1).r, 0.0f);
    EXPECT_EQ(map.at(2, 2).r, smooth_texel(2, 2).r);
}

TEST(Environment, BuiltinConstantIsUniform) {
    const EnvironmentMap one = load_environment("builtin:constant");
    EXPECT_EQ(one.width, 2 * one.height);
    for (const glm::vec3& t : one.texels) ASSERT_EQ(t, glm::vec3(1.0f));
    const EnvironmentMap two = load_environment("builtin:constant:2.5");
    for (const glm::vec3& t : two.texels) ASSERT_EQ(t, glm::vec3(2.5f));
    expect_input_error_naming("builtin:constant:-1", "builtin:constant:-1");
    expect_input_error_naming("builtin:constant:abc", "not a number");
    expect_input_error_naming("builtin:nothing", "unknown builtin");
}

TEST(Environment, BuiltinSkyRejectsBadKeys) {
    expect_input_error_naming("builtin:sky:colour=3", "unknown key 'colour'");
    expect_input_error_naming("builtin:sky:elevation=100", "elevation");
    expect_input_error_naming("builtin:sky:width=101", "width must be an even integer");
    expect_input_error_naming("builtin:sky:size", "not key=value");
}

// Integral of luminance over the upper hemisphere.
double upper_luminance(const EnvironmentMap& map) {
    double sum = 0.0;
    for (int j = 0; j < map.height / 2; ++j)
        for (int i = 0; i < map.width; ++i)
            sum += latlong::luminance(glm::dvec3(map.at(i, j))) * latlong::texel_solid_angle(j, map.width, map.height);
    return sum;
}

TEST(Environment, BuiltinSkySunIsABrightDiscCarryingMostOfTheLight) {
    const SkyParameters defaults;
    const EnvironmentMap sky = load_environment("builtin:sky");
    ASSERT_EQ(sky.width, 1024);
    const EnvironmentMap no_sun = load_environment("builtin:sky:intensity=0");
    // The disc's light: what the sun adds above the horizon, against radiance x solid angle x colour.
    const double disc = upper_luminance(sky) - upper_luminance(no_sun);
    const double radius = 0.5 * defaults.size_degrees * std::numbers::pi / 180.0;
    const double expected = defaults.intensity * 2.0 * std::numbers::pi * (1.0 - std::cos(radius)) *
                            latlong::luminance(glm::dvec3(1.0, 0.93, 0.82));
    EXPECT_NEAR(disc, expected, 0.03 * expected);
    // A significant share of all the light, so that shadows are clear.
    double total = 0.0;
    for (int j = 0; j < sky.height; ++j)
        for (int i = 0; i < sky.width; ++i)
            total +=
                latlong::luminance(glm::dvec3(sky.at(i, j))) * latlong::texel_solid_angle(j, sky.width, sky.height);
    EXPECT_GT(disc / total, 0.5);
    // The brightest texel is the sun's direction.
    size_t brightest = 0;
    for (size_t t = 0; t < sky.texels.size(); ++t)
        if (sky.texels[t].r > sky.texels[brightest].r) brightest = t;
    const glm::dvec3 at = latlong::texel_direction(int(brightest % 1024), int(brightest / 1024), 1024, 512);
    EXPECT_LT(std::acos(glm::dot(at, sun_direction(defaults))), 2.0 * std::numbers::pi / 512);
    // A dim ground: darker than the sky, not black.
    double ground = 0.0, sky_mean = 0.0;
    for (int j = 0; j < 256; ++j)
        for (int i = 0; i < 1024; ++i) {
            sky_mean += latlong::luminance(glm::dvec3(no_sun.at(i, j)));
            ground += latlong::luminance(glm::dvec3(no_sun.at(i, 511 - j)));
        }
    EXPECT_GT(ground, 0.0);
    EXPECT_LT(ground, 0.5 * sky_mean);
}

TEST(Environment, BuiltinSkyTimeMovesTheSunAlongItsArc) {
    SkyParameters sky;
    const glm::dvec3 noon = sun_direction(sky);
    sky.time_hours = 6.0;
    EXPECT_NEAR(sun_direction(sky).y, 0.0, 1e-12);  // sunrise on the horizon
    sky.time_hours = 18.0;
    EXPECT_NEAR(sun_direction(sky).y, 0.0, 1e-12);
    sky.time_hours = 9.0;
    const glm::dvec3 morning = sun_direction(sky);
    EXPECT_GT(morning.y, 0.0);
    EXPECT_LT(morning.y, noon.y);
    EXPECT_NEAR(glm::length(morning), 1.0, 1e-12);
    // The spec's time key agrees, and at night the ground hides the sun.
    const EnvironmentMap at_noon = load_environment("builtin:sky:time=12,width=256");
    const EnvironmentMap default_sky = load_environment("builtin:sky:width=256");
    EXPECT_EQ(at_noon.texels, default_sky.texels);
    const EnvironmentMap night = load_environment("builtin:sky:time=2,width=256");
    const EnvironmentMap night_no_sun = load_environment("builtin:sky:time=2,width=256,intensity=0");
    EXPECT_NEAR(upper_luminance(night), upper_luminance(night_no_sun), 1e-9);
}

TEST(Environment, AnimationClockMovesOnlyBuiltinSkysSun) {
    EXPECT_EQ(environment_at_time("builtin:sky", 0.0), "builtin:sky");
    EXPECT_EQ(environment_at_time("builtin:constant", 5.0), "builtin:constant");
    EXPECT_EQ(environment_at_time("/maps/city.exr", 5.0), "/maps/city.exr");
    // One hour per second, from noon or from the spec's own time; the other keys stay.
    const auto sun_at = [](const std::string& spec) {
        const EnvironmentMap map = load_environment(spec);
        size_t brightest = 0;
        for (size_t t = 0; t < map.texels.size(); ++t)
            if (map.texels[t].r > map.texels[brightest].r) brightest = t;
        return latlong::texel_direction(int(brightest % size_t(map.width)), int(brightest / size_t(map.width)),
                                        map.width, map.height);
    };
    SkyParameters sky;
    sky.time_hours = 13.5;
    EXPECT_LT(std::acos(glm::dot(sun_at(environment_at_time("builtin:sky:width=256", 1.5)), sun_direction(sky))),
              2.0 * std::numbers::pi / 128);
    sky.time_hours = 10.0;
    sky.azimuth_degrees = 200.0;
    EXPECT_LT(std::acos(glm::dot(sun_at(environment_at_time("builtin:sky:time=8,azimuth=200,width=256", 2.0)),
                                 sun_direction(sky))),
              2.0 * std::numbers::pi / 128);
}

}  // namespace
}  // namespace envshadow
