#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/image.h"

namespace envshadow {
namespace {

std::filesystem::path temp_dir() {
    auto dir = std::filesystem::temp_directory_path() /
               ("envshadow_core_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    std::filesystem::create_directories(dir);
    return dir;
}

TEST(Image, ExrRoundTripKeepsFloatValues) {
    Image image(5, 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) image.at(x, y) = glm::vec4(x * 1000.5f, y * 1e-4f, -0.003f, 0.25f * x);
    const auto path = temp_dir() / "round_trip.exr";
    write_exr(path, image);
    const ExrContents back = read_exr(path);
    ASSERT_EQ(back.image.width, 5);
    ASSERT_EQ(back.image.height, 3);
    EXPECT_TRUE(back.had_alpha);
    for (size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 4; ++c) EXPECT_FLOAT_EQ(back.image.pixels[i][c], image.pixels[i][c]);
}

TEST(Image, ReadingAMissingOrCorruptExrNamesTheFile) {
    const auto missing = temp_dir() / "missing.exr";
    try {
        read_exr(missing);
        FAIL() << "no exception";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos);
    }
    const auto garbage = temp_dir() / "garbage.exr";
    {
        std::FILE* f = std::fopen(garbage.string().c_str(), "wb");
        std::fputs("not an exr file at all", f);
        std::fclose(f);
    }
    EXPECT_THROW(read_exr(garbage), InputError);
}

TEST(Image, TonemapIsMonotonicAndMapsZeroToBlack) {
    Image image(4, 1);
    image.at(0, 0) = glm::vec4(0, 0, 0, 1);
    image.at(1, 0) = glm::vec4(0.18f, 0.18f, 0.18f, 1);
    image.at(2, 0) = glm::vec4(1, 1, 1, 1);
    image.at(3, 0) = glm::vec4(100, 100, 100, 1);
    const Image8 out = tonemap_to_srgb8(image);
    EXPECT_EQ(out.at(0, 0)[0], 0);
    EXPECT_LT(out.at(1, 0)[0], out.at(2, 0)[0]);
    EXPECT_LT(out.at(2, 0)[0], out.at(3, 0)[0]);
    EXPECT_GE(out.at(3, 0)[0], 250);
    EXPECT_EQ(out.at(3, 0)[3], 255);
}

TEST(Image, SrgbEncodeMatchesTheStandardAtKnownPoints) {
    EXPECT_FLOAT_EQ(srgb_encode(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(srgb_encode(1.0f), 1.0f);
    EXPECT_NEAR(srgb_encode(0.18f), 0.4613f, 1e-3f);    // mid grey
    EXPECT_NEAR(srgb_encode(0.002f), 0.02584f, 1e-5f);  // linear segment
}

TEST(Image, PngRoundTrip) {
    Image8 image(3, 2);
    for (size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = std::uint8_t(i * 10);
    const auto path = temp_dir() / "round_trip.png";
    write_png(path, image);
    const Image8 back = read_png(path);
    ASSERT_EQ(back.width, 3);
    ASSERT_EQ(back.height, 2);
    EXPECT_EQ(back.rgba, image.rgba);
}

}  // namespace
}  // namespace envshadow
