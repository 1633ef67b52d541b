// load_environment (environment.h) against files written here by other writers: core's write_exr
// (float), OpenEXR's own RGBA writers (half scanlines, tiles) and stb's Radiance writer; broken and
// hostile files; the builtins; and what decompose() does with degenerate maps (black, tiny).
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <ImfArray.h>
#include <ImfRgbaFile.h>
#include <ImfTiledRgbaFile.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <stb_image_write.h>
#include <sys/wait.h>
#include <unistd.h>

#include "contract_helpers.h"
#include "core/error.h"
#include "core/image.h"

namespace envshadow::contract {
namespace {

namespace fs = std::filesystem;

// A folder of this test's own (ctest runs tests as parallel processes).
class EnvContractLoader : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("envshadow_env_contract_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    fs::path dir_;
};

// A W x H picture with values over many magnitudes (and a bright top row, to catch a vertical flip).
Image test_image(int width, int height, std::uint32_t seed = 1) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> exponent(-6.0f, 6.0f);
    Image image(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            image.at(x, y) =
                glm::vec4(std::exp2(exponent(rng)), std::exp2(exponent(rng)), std::exp2(exponent(rng)), 1.0f);
    for (int x = 0; x < width; ++x) image.at(x, 0) = glm::vec4(1000.0f, 2000.0f, 3000.0f, 1.0f);
    return image;
}

// What became of loading a hostile file. The load runs in a child process with a time limit, so that a
// crash or a hang is reported (which file, which flip) instead of ending or stalling the test binary.
struct Outcome {
    enum Kind { loaded, input_error, wrong, crashed, hung } kind;
    std::string message;
};

Outcome load_in_child(const std::string& file) {
    int fds[2];
    if (::pipe(fds) != 0) return {Outcome::wrong, "pipe() failed"};
    const pid_t pid = ::fork();
    if (pid < 0) return {Outcome::wrong, "fork() failed"};
    if (pid == 0) {
        ::close(fds[0]);
        std::string out;
        try {
            const EnvironmentMap map = load_environment(file);
            out = "L";
            if (map.width != 2 * map.height || map.texels.size() != std::size_t(map.width) * std::size_t(map.height))
                out = "Wloaded a " + std::to_string(map.width) + "x" + std::to_string(map.height) + " map";
            for (const glm::vec3& t : map.texels)
                for (int c = 0; c < 3; ++c)
                    if (!(std::isfinite(t[c]) && t[c] >= 0.0f))
                        out = "Wloaded a texel component " + std::to_string(t[c]);
        } catch (const InputError& e) {
            out = std::string(std::string(e.what()).find(file) != std::string::npos ? "E" : "W") +
                  "InputError not naming the file: " + e.what();
        } catch (const std::exception& e) {
            out = std::string("Wthrew something other than InputError: ") + e.what();
        } catch (...) {
            out = "Wthrew a non-standard exception";
        }
        [[maybe_unused]] const ssize_t written = ::write(fds[1], out.data(), out.size());
        ::_exit(0);
    }
    ::close(fds[1]);
    std::string out;
    pollfd poll_fd{fds[0], POLLIN, 0};
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);  // a load takes milliseconds
    bool hung = false;
    for (;;) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0 || ::poll(&poll_fd, 1, int(left.count())) == 0) {
            hung = true;
            break;
        }
        char buffer[512];
        const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
        if (n <= 0) break;
        out.append(buffer, std::size_t(n));
    }
    ::close(fds[0]);
    if (hung) ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (hung) return {Outcome::hung, "no answer after 3 s"};
    if (WIFSIGNALED(status)) return {Outcome::crashed, "killed by signal " + std::to_string(WTERMSIG(status))};
    if (out.empty()) return {Outcome::crashed, "no answer"};
    const Outcome::Kind kind = out[0] == 'L' ? Outcome::loaded : out[0] == 'E' ? Outcome::input_error : Outcome::wrong;
    return {kind, out.substr(1)};
}

template <class F>
void expect_input_error_naming(const std::string& file, F&& load, const std::string& what) {
    try {
        load();
        ADD_FAILURE() << what << ": loaded without an error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(file), std::string::npos)
            << what << ": message does not name the file: " << e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << what << ": threw something other than InputError: " << e.what();
    }
}

std::vector<char> read_bytes(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& file, const std::vector<char>& bytes, std::size_t count) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(count));
}

// --- good files ------------------------------------------------------------------------------------

TEST_F(EnvContractLoader, FloatExrRoundTripIsExact) {
    const Image image = test_image(64, 32);
    write_exr(path("float.exr"), image);
    EnvironmentLoadReport report;
    const EnvironmentMap map = load_environment(path("float.exr"), {}, &report);
    ASSERT_EQ(map.width, 64);
    ASSERT_EQ(map.height, 32);
    for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 64; ++i) ASSERT_EQ(map.at(i, j), glm::vec3(image.at(i, j))) << i << "," << j;
    EXPECT_EQ(report.negative_clamped, 0);
    EXPECT_EQ(report.invalid_clamped, 0);
}

TEST_F(EnvContractLoader, HalfExrWrittenByOpenExrLoadsExactly) {
    const Image image = test_image(64, 32, 2);
    Imf::Array2D<Imf::Rgba> pixels(32, 64);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x) {
            const glm::vec4 p = image.at(x, y);
            pixels[y][x] = Imf::Rgba(p.r, p.g, p.b, 1.0f);
        }
    {
        Imf::RgbaOutputFile file(path("half.exr").c_str(), 64, 32, Imf::WRITE_RGBA);
        file.setFrameBuffer(&pixels[0][0], 1, 64);
        file.writePixels(32);
    }
    const EnvironmentMap map = load_environment(path("half.exr"));
    ASSERT_EQ(map.width, 64);
    ASSERT_EQ(map.height, 32);
    for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 64; ++i)
            ASSERT_EQ(map.at(i, j), glm::vec3(float(pixels[j][i].r), float(pixels[j][i].g), float(pixels[j][i].b)))
                << i << "," << j;
}

TEST_F(EnvContractLoader, TiledExrLoadsExactly) {
    const Image image = test_image(128, 64, 3);
    Imf::Array2D<Imf::Rgba> pixels(64, 128);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 128; ++x) {
            const glm::vec4 p = image.at(x, y);
            pixels[y][x] = Imf::Rgba(p.r, p.g, p.b, 1.0f);
        }
    {
        // 48 x 24 tiles: partial tiles at the right and bottom edges too.
        Imf::TiledRgbaOutputFile file(path("tiled.exr").c_str(), 128, 64, 48, 24, Imf::ONE_LEVEL, Imf::ROUND_DOWN,
                                      Imf::WRITE_RGB);
        file.setFrameBuffer(&pixels[0][0], 1, 128);
        file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
    }
    const EnvironmentMap map = load_environment(path("tiled.exr"));
    ASSERT_EQ(map.width, 128);
    ASSERT_EQ(map.height, 64);
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 128; ++i)
            ASSERT_EQ(map.at(i, j), glm::vec3(float(pixels[j][i].r), float(pixels[j][i].g), float(pixels[j][i].b)))
                << i << "," << j;
}

// RGBE keeps 8 bits of mantissa for the largest component of a texel (stb truncates when writing and
// when reading): each component comes back within 1/64 of the texel's largest.
TEST_F(EnvContractLoader, RadianceHdrLoadsWithinRgbePrecision) {
    const Image image = test_image(64, 32, 4);
    std::vector<float> rgb;
    for (const glm::vec4& p : image.pixels) rgb.insert(rgb.end(), {p.r, p.g, p.b});
    ASSERT_NE(stbi_write_hdr(path("map.hdr").c_str(), 64, 32, 3, rgb.data()), 0);
    const EnvironmentMap map = load_environment(path("map.hdr"));
    ASSERT_EQ(map.width, 64);
    ASSERT_EQ(map.height, 32);
    for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 64; ++i) {
            const glm::vec4 p = image.at(i, j);
            const float largest = std::max({p.r, p.g, p.b});
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(map.at(i, j)[c], p[c], largest / 64.0f) << i << "," << j << " channel " << c;
        }
}

// The smallest lat-long map (two texels, one row) is a map.
TEST_F(EnvContractLoader, TwoByOneMapLoads) {
    write_exr(path("tiny.exr"), Image(2, 1, glm::vec4(1.0f)));
    const EnvironmentMap map = load_environment(path("tiny.exr"));
    EXPECT_EQ(map.width, 2);
    EXPECT_EQ(map.height, 1);
}

// --- values that need cleaning -----------------------------------------------------------------------

TEST_F(EnvContractLoader, NegativeComponentsAreClampedAndCounted) {
    Image image = test_image(64, 32, 5);
    long long negatives = 0;
    for (std::size_t t = 0; t < image.pixels.size(); t += 7) {
        image.pixels[t].g = -0.003f;  // what real photographs hold
        ++negatives;
        if (t % 3 == 0) {
            image.pixels[t].r = -2.0f;
            ++negatives;
        }
    }
    write_exr(path("negative.exr"), image);
    EnvironmentLoadReport report;
    const EnvironmentMap map = load_environment(path("negative.exr"), {}, &report);
    EXPECT_EQ(report.negative_clamped, negatives);
    EXPECT_EQ(report.invalid_clamped, 0);
    for (std::size_t t = 0; t < image.pixels.size(); ++t)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(map.texels[t][c], std::max(0.0f, image.pixels[t][c])) << t;
}

TEST_F(EnvContractLoader, NonFiniteValuesAreAnInputErrorNamingTheFileUnlessClamped) {
    Image image = test_image(64, 32, 6);
    image.pixels[5].r = std::numeric_limits<float>::quiet_NaN();
    image.pixels[77].g = std::numeric_limits<float>::infinity();
    image.pixels[300].b = -std::numeric_limits<float>::infinity();
    image.pixels[301].b = 1e35f;  // environment.h: above 1e30 counts as invalid
    image.pixels[400].r = -1.0f;  // negative: clamped and counted separately
    write_exr(path("nan.exr"), image);
    expect_input_error_naming(
        path("nan.exr"), [&] { load_environment(path("nan.exr")); }, "NaN/Inf without clamp_invalid");

    EnvironmentLoadReport report;
    const EnvironmentMap map = load_environment(path("nan.exr"), {.clamp_invalid = true}, &report);
    EXPECT_EQ(report.invalid_clamped, 4);
    EXPECT_EQ(report.negative_clamped, 1);
    EXPECT_EQ(map.texels[5].r, 0.0f);
    EXPECT_EQ(map.texels[77].g, 0.0f);
    EXPECT_EQ(map.texels[300].b, 0.0f);
    EXPECT_EQ(map.texels[301].b, 0.0f);
    EXPECT_EQ(map.texels[400].r, 0.0f);
    EXPECT_EQ(map.texels[5].g, image.pixels[5].g) << "the other components of a texel are kept";
}

// --- bad files -------------------------------------------------------------------------------------

TEST_F(EnvContractLoader, WrongAspectRatioIsAnInputErrorNamingTheFile) {
    write_exr(path("square.exr"), Image(64, 64, glm::vec4(1.0f)));
    write_exr(path("wide.exr"), Image(64, 16, glm::vec4(1.0f)));
    write_exr(path("one_by_two.exr"), Image(1, 2, glm::vec4(1.0f)));
    for (const char* name : {"square.exr", "wide.exr", "one_by_two.exr"})
        expect_input_error_naming(
            path(name), [&] { load_environment(path(name)); }, name);
    std::vector<float> rgb(40 * 30 * 3, 1.0f);
    ASSERT_NE(stbi_write_hdr(path("odd.hdr").c_str(), 40, 30, 3, rgb.data()), 0);
    expect_input_error_naming(
        path("odd.hdr"), [&] { load_environment(path("odd.hdr")); }, "40x30 .hdr");
}

// A header claiming 32768 x 16384 (over the 16384 x 8192 limit) and no pixels: refused, without
// allocating the 6 GiB it claims.
TEST_F(EnvContractLoader, OversizedHeaderIsAnInputError) {
    std::ofstream(path("huge.hdr"), std::ios::binary) << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16384 +X 32768\n";
    expect_input_error_naming(
        path("huge.hdr"), [&] { load_environment(path("huge.hdr")); }, "32768x16384 .hdr");
}

TEST_F(EnvContractLoader, MissingAndForeignFilesAreInputErrorsNamingThem) {
    const std::string missing = path("no_such_map.exr");
    expect_input_error_naming(
        missing, [&] { load_environment(missing); }, "missing file");
    std::ofstream(path("text.exr")) << "this is not an image\n";
    expect_input_error_naming(
        path("text.exr"), [&] { load_environment(path("text.exr")); }, "a text file");
    std::ofstream(path("empty.hdr")) << "";
    expect_input_error_naming(
        path("empty.hdr"), [&] { load_environment(path("empty.hdr")); }, "an empty file");
}

// Every truncation of valid files fails cleanly, and no single bit flip crashes or hangs the loader or
// makes it throw anything but an InputError naming the file (a flip in pixel data may load, as a valid
// map). .hdr files too: their run-length coding has its own ways to go wrong.
TEST_F(EnvContractLoader, TruncatedAndBitFlippedFilesAreInputErrorsNotCrashes) {
    write_exr(path("good.exr"), test_image(64, 32, 7));
    {
        Imf::Array2D<Imf::Rgba> pixels(32, 64);
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 64; ++x) pixels[y][x] = Imf::Rgba(float(x), float(y), 1.0f, 1.0f);
        Imf::TiledRgbaOutputFile file(path("good_tiled.exr").c_str(), 64, 32, 16, 16, Imf::ONE_LEVEL, Imf::ROUND_DOWN,
                                      Imf::WRITE_RGB);
        file.setFrameBuffer(&pixels[0][0], 1, 64);
        file.writeTiles(0, file.numXTiles() - 1, 0, file.numYTiles() - 1);
    }
    const Image hdr_image = test_image(64, 32, 8);
    std::vector<float> rgb;
    for (const glm::vec4& p : hdr_image.pixels) rgb.insert(rgb.end(), {p.r, p.g, p.b});
    ASSERT_NE(stbi_write_hdr(path("good.hdr").c_str(), 64, 32, 3, rgb.data()), 0);

    for (const char* name : {"good.exr", "good_tiled.exr", "good.hdr"}) {
        const std::vector<char> bytes = read_bytes(path(name));
        ASSERT_GT(bytes.size(), 64u);
        const std::string file = path(std::string("broken") + fs::path(name).extension().string());
        int failures = 0;
        auto check = [&](const std::string& what, bool may_load) {
            const Outcome outcome = load_in_child(file);
            const bool ok = outcome.kind == Outcome::input_error || (may_load && outcome.kind == Outcome::loaded);
            if (!ok && ++failures <= 5)
                ADD_FAILURE() << name << " " << what << ": "
                              << (outcome.kind == Outcome::loaded ? std::string("loaded") : outcome.message);
            return outcome.kind;
        };
        for (std::size_t length :
             {std::size_t(0), std::size_t(1), std::size_t(3), std::size_t(4), std::size_t(8), std::size_t(40),
              bytes.size() / 4, bytes.size() / 2, bytes.size() - 16, bytes.size() - 1}) {
            write_bytes(file, bytes, length);
            check("cut to " + std::to_string(length) + " of " + std::to_string(bytes.size()) + " bytes", false);
        }
        // One bit of every byte of the first 320 (the header and offset tables; the top bit every other
        // byte, where sizes and offsets turn huge or negative), then of every 61st byte; stops after a few
        // failures (a hang costs 3 s).
        int refused = 0, flips = 0;
        for (std::size_t at = 0; at < bytes.size() && failures < 5; at += at < 320 ? 1 : 61)
            for (int bit : {at % 2 ? 7 : int(at / 2 % 7)}) {
                std::vector<char> flipped = bytes;
                flipped[at] = char(flipped[at] ^ (1 << bit));
                write_bytes(file, flipped, flipped.size());
                ++flips;
                refused += check("with bit " + std::to_string(bit) + " of byte " + std::to_string(at) + " flipped",
                                 true) == Outcome::input_error;
            }
        EXPECT_EQ(failures, 0) << name << ": " << failures << " truncations and flips crashed, hung or threw wrongly";
        EXPECT_GT(refused, 0) << name << ": none of " << flips << " flips was noticed";
    }
}

// --- builtins --------------------------------------------------------------------------------------

TEST(EnvContractBuiltins, ConstantIsUniform) {
    const EnvironmentMap map = load_environment("builtin:constant:2.5");
    EXPECT_EQ(map.width, kConstantEnvironmentWidth);
    EXPECT_EQ(map.height, kConstantEnvironmentWidth / 2);
    for (const glm::vec3& t : map.texels) ASSERT_EQ(t, glm::vec3(2.5f));
    EXPECT_EQ(load_environment("builtin:constant").texels.front(), glm::vec3(1.0f));
}

// environment.h: the sun's disc carries about two thirds of ∫ L dω (here in luminance) and sits at
// sun_direction(); the sun rises at 6 h on the horizon at azimuth - 90 and culminates at 12 h.
TEST(EnvContractBuiltins, SkySunIsWhereAndAsBrightAsDocumented) {
    for (const auto& [spec, sky] :
         {std::pair<std::string, SkyParameters>{"builtin:sky", SkyParameters{}},
          {"builtin:sky:elevation=50,azimuth=200,time=10", SkyParameters{50, 200, 1.5, 25000, 10}}}) {
        const EnvironmentMap& map = cached_map(spec);
        EXPECT_EQ(map.width, 1024) << spec;
        EXPECT_EQ(map.height, 512) << spec;
        const glm::dvec3 sun = sun_direction(sky);
        EXPECT_NEAR(glm::length(sun), 1.0, 1e-9);
        const double disc = 0.5 * sky.size_degrees * std::numbers::pi / 180.0;
        const double texel = std::numbers::pi / map.height;
        double total = 0.0, near_sun = 0.0, brightest = -1.0;
        glm::dvec3 brightest_direction(0.0);
        for (int j = 0; j < map.height; ++j) {
            const double dw = latlong::texel_solid_angle(j, map.width, map.height);
            for (int i = 0; i < map.width; ++i) {
                const glm::dvec3 d = latlong::texel_direction(i, j, map.width, map.height);
                const double lum = latlong::luminance(glm::dvec3(map.at(i, j)));
                total += lum * dw;
                if (std::acos(std::min(1.0, glm::dot(d, sun))) < disc + 2.0 * texel) near_sun += lum * dw;
                if (lum > brightest) brightest = lum, brightest_direction = d;
            }
        }
        EXPECT_GT(near_sun / total, 0.55) << spec;
        EXPECT_LT(near_sun / total, 0.80) << spec;
        EXPECT_LT(std::acos(std::min(1.0, glm::dot(brightest_direction, sun))), disc + 1.5 * texel) << spec;
    }
    SkyParameters morning;
    morning.time_hours = 6.0;
    const glm::dvec3 rise = sun_direction(morning);
    EXPECT_NEAR(rise.y, 0.0, 1e-9);
    const double azimuth = std::atan2(rise.z, rise.x) * 180.0 / std::numbers::pi;
    EXPECT_NEAR(azimuth, morning.azimuth_degrees - 90.0, 1e-6);
    const glm::dvec3 noon = sun_direction(SkyParameters{});
    EXPECT_NEAR(std::asin(noon.y) * 180.0 / std::numbers::pi, SkyParameters{}.elevation_degrees, 1e-6);
    EXPECT_EQ(load_environment("builtin:sky:width=64").width, 64);
}

TEST(EnvContractBuiltins, BadSpecsAreInputErrorsNamingTheSpec) {
    for (const char* spec :
         {"builtin:nothing", "builtin:constant:abc", "builtin:constant:-1", "builtin:sky:elevation=91",
          "builtin:sky:colour=3", "builtin:sky:elevation", "builtin:sky:width=63"})
        expect_input_error_naming(
            spec, [&] { load_environment(spec); }, spec);
}

// --- degenerate maps through decompose() -----------------------------------------------------------

// importance.h: an all-black map falls back to solid-angle importance, "so every method still gives
// well-defined cells (uniform by solid angle)".
TEST_F(EnvContractLoader, BlackMapGivesWellDefinedCells) {
    write_exr(path("black.exr"), Image(128, 64, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f)));
    const EnvironmentMap map = load_environment(path("black.exr"));
    for (Method method : kAllMethods)
        for (int lights : {1, 16, 64}) {
            const std::string context = describe("black", method, lights);
            const Decomposition d = decompose(map, {.method = method, .lights = lights});
            EXPECT_TRUE(d.uniform_importance) << context;
            EXPECT_TRUE(count_as_promised(method, lights, d.cells.size()))
                << context << ": " << d.cells.size() << " cells";
            expect_cells_contract(map, d, context);
            for (const Cell& cell : d.cells) EXPECT_EQ(cell.radiance, glm::vec3(0.0f)) << context;
            if (method == Method::ccvt) {
                const std::vector<double> importance = texel_importance(map);
                EXPECT_LT(
                    coefficient_of_variation(cell_sums(map, importance, d.texel_cell, d.cells.size()).solid_angle), 0.1)
                    << context << ": equal importance is equal solid angle here";
            }
        }
}

// cells.h: lights outside 1..256 are a UsageError; more lights than texels an InputError; as many as
// texels is allowed.
TEST(EnvContractDegenerate, LightCountLimits) {
    EnvironmentMap tiny;
    tiny.width = 2;
    tiny.height = 1;
    tiny.texels = {glm::vec3(1.0f), glm::vec3(3.0f)};
    tiny.source = "tiny-2x1";
    for (Method method : kAllMethods) {
        EXPECT_THROW(decompose(tiny, {.method = method, .lights = 0}), UsageError);
        EXPECT_THROW(decompose(tiny, {.method = method, .lights = kMaxLights + 1}), UsageError);
        EXPECT_THROW(decompose(tiny, {.method = method, .lights = 3}), InputError) << to_string(method);
        for (int lights : {1, 2}) {
            const std::string context = describe("2x1", method, lights);
            const Decomposition d = decompose(tiny, {.method = method, .lights = lights});
            ASSERT_GE(d.cells.size(), 1u) << context;
            ASSERT_LE(d.cells.size(), std::size_t(lights)) << context;
            expect_cells_contract(tiny, d, context);
        }
        // N = 2 on two texels: one texel each.
        const Decomposition two = decompose(tiny, {.method = method, .lights = 2});
        if (two.cells.size() == 2) {
            EXPECT_NE(two.texel_cell[0], two.texel_cell[1]) << to_string(method);
        }
    }
}

TEST(EnvContractDegenerate, AsManyLightsAsTexels) {
    EnvironmentMap small;
    small.width = 16;
    small.height = 8;
    small.source = "small-16x8";
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 16; ++i) small.texels.push_back(glm::vec3(1.0f + float((i * 7 + j * 3) % 5)));
    for (Method method : kAllMethods) {
        EXPECT_THROW(decompose(small, {.method = method, .lights = 129}), InputError) << to_string(method);
        const std::string context = describe("16x8", method, 128);
        const Decomposition d = decompose(small, {.method = method, .lights = 128});
        EXPECT_TRUE(count_as_promised(method, 128, d.cells.size())) << context << ": " << d.cells.size() << " cells";
        expect_cells_contract(small, d, context);
    }
}

}  // namespace
}  // namespace envshadow::contract
