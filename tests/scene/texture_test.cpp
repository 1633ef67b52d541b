// scene/texture.h: the sRGB decode (and data textures read as stored) and the reference's bilinear lookup with glTF's
// wrap modes, on textures small enough to work out by hand.
#include "scene/texture.h"

#include <cmath>
#include <memory>

#include <gtest/gtest.h>

namespace envshadow {
namespace {

// A width x 1 texture whose texel i has the same sRGB value `values[i]` in r, g and b.
MaterialTexture row(std::initializer_list<std::uint8_t> values, TextureWrap wrap = TextureWrap::repeat) {
    auto image = std::make_shared<TextureImage>();
    image->width = int(values.size());
    image->height = 1;
    for (const std::uint8_t v : values) image->rgba.insert(image->rgba.end(), {v, v, v, 255});
    MaterialTexture t;
    t.image = image;
    t.wrap_s = t.wrap_t = wrap;
    return t;
}

TEST(Texture, SrgbDecodeFollowsIec61966) {
    EXPECT_EQ(srgb8_to_linear(0), 0.0f);
    EXPECT_FLOAT_EQ(srgb8_to_linear(255), 1.0f);
    EXPECT_NEAR(srgb8_to_linear(10), 10.0 / 255.0 / 12.92, 1e-7);  // the linear segment
    EXPECT_NEAR(srgb8_to_linear(188), 0.5029, 1e-4);               // sRGB 188 is about half the light
}

TEST(Texture, TexelCentresGiveTheTexelAndMidpointsTheMeanOfTheDecodedPair) {
    const MaterialTexture t = row({0, 255});
    EXPECT_NEAR(sample_linear_rgb(t, {0.25f, 0.5f}).r, 0.0, 1e-6);
    EXPECT_NEAR(sample_linear_rgb(t, {0.75f, 0.5f}).r, 1.0, 1e-6);
    // Filtered after decoding, as GL filters sRGB textures: the mean of 0 and 1, not of the codes.
    EXPECT_NEAR(sample_linear_rgb(t, {0.5f, 0.5f}).g, 0.5, 1e-6);
}

TEST(Texture, DataTexturesAreReadAsStored) {
    MaterialTexture t = row({128, 188});
    t.srgb = false;  // occlusion: R / 255, no decode
    EXPECT_NEAR(sample_linear_rgb(t, {0.25f, 0.5f}).r, 128.0 / 255.0, 1e-6);
    EXPECT_NEAR(sample_linear_rgb(t, {0.5f, 0.5f}).g, (128.0 + 188.0) / 2.0 / 255.0, 1e-6);
    t.srgb = true;
    EXPECT_NEAR(sample_linear_rgb(t, {0.75f, 0.5f}).r, srgb8_to_linear(188), 1e-6);
}

TEST(Texture, WrapModesBeyondTheEdges) {
    // u = 1.25 lies at the first texel's centre when repeating, past the last texel when clamping and
    // at the mirror image of u = 0.75 when mirroring.
    EXPECT_NEAR(sample_linear_rgb(row({0, 255}, TextureWrap::repeat), {1.25f, 0.5f}).r, 0.0, 1e-6);
    EXPECT_NEAR(sample_linear_rgb(row({0, 255}, TextureWrap::clamp_to_edge), {1.25f, 0.5f}).r, 1.0, 1e-6);
    EXPECT_NEAR(sample_linear_rgb(row({0, 255}, TextureWrap::mirrored_repeat), {1.25f, 0.5f}).r, 1.0, 1e-6);
    EXPECT_NEAR(sample_linear_rgb(row({0, 255}, TextureWrap::mirrored_repeat), {1.75f, 0.5f}).r, 0.0, 1e-6);
    EXPECT_NEAR(sample_linear_rgb(row({0, 255}, TextureWrap::repeat), {-0.25f, 0.5f}).r, 1.0, 1e-6);
    // Repeat joins the last texel to the first across the seam: half way at u = 0 (and 1).
    EXPECT_NEAR(sample_linear_rgb(row({0, 255}, TextureWrap::repeat), {0.0f, 0.5f}).r, 0.5, 1e-6);
    EXPECT_NEAR(sample_linear_rgb(row({0, 255}, TextureWrap::clamp_to_edge), {0.0f, 0.5f}).r, 0.0, 1e-6);
}

TEST(Texture, NearestPicksTheTexelUnderTheCoordinate) {
    MaterialTexture t = row({0, 255, 0});
    t.nearest = true;
    EXPECT_EQ(sample_linear_rgb(t, {0.40f, 0.5f}).r, 1.0f);
    EXPECT_EQ(sample_linear_rgb(t, {0.30f, 0.5f}).r, 0.0f);
}

TEST(Texture, NonFiniteCoordinatesReadATexelNotGarbage) {
    const glm::vec3 c = sample_linear_rgb(row({0, 255}), {NAN, INFINITY});
    EXPECT_TRUE(std::isfinite(c.r) && c.r >= 0.0f && c.r <= 1.0f);
}

}  // namespace
}  // namespace envshadow
