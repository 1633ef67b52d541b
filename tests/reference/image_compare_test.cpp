// `compare`'s measures: zero for identical images, the known value for a known perturbation, the
// pixel selection by alpha or mask, and one-line errors for mismatched input.
#include "reference/image_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <glm/vec3.hpp>
#include <limits>

#include "core/error.h"

namespace envshadow::testing {
namespace {

using reference::compare_images;

// Left half covered by an object (alpha 1) with a pattern, right half background (alpha 0).
Image half_covered(int width = 16, int height = 8) {
    Image image(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            image.at(x, y) =
                glm::vec4(0.1f + 0.05f * float(x), 0.3f + 0.02f * float(y), 0.7f, x < width / 2 ? 1.0f : 0.0f);
    return image;
}

TEST(ImageCompare, IdenticalImagesHaveNoError) {
    const Image a = half_covered();
    const reference::Comparison c = compare_images(a, a);
    EXPECT_EQ(c.rel_rmse, 0.0);
    EXPECT_TRUE(std::isinf(c.psnr));
    EXPECT_EQ(c.pixels, 8 * 8);
}

TEST(ImageCompare, ScaledImageHasTheScaleAsRelativeError) {
    // B = 1.01 A on the object pixels: rel_rmse = 0.01 whatever A is; changes on the background don't count.
    const Image a = half_covered();
    Image b = a;
    for (glm::vec4& p : b.pixels) {
        if (p.a > 0.5f)
            p = glm::vec4(glm::vec3(p) * 1.01f, p.a);
        else
            p = glm::vec4(100.0f);
    }
    EXPECT_NEAR(compare_images(a, b).rel_rmse, 0.01, 1e-6);
    // A constant image (peak = value) off by 1%: PSNR = 10 log10(1 / 0.01^2) = 40 dB.
    const Image flat(4, 4, glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
    const Image off(4, 4, glm::vec4(0.505f, 0.505f, 0.505f, 1.0f));
    const reference::Comparison c = compare_images(flat, off);
    EXPECT_NEAR(c.rel_rmse, 0.01, 1e-6);
    EXPECT_NEAR(c.psnr, 40.0, 1e-3);
    EXPECT_EQ(c.pixels, 16);
}

TEST(ImageCompare, OneWrongPixelOfFour) {
    // Four pixels of value 1 (RGB), one of them off by 0.4 in red: sqrt(0.16 / 12).
    const Image a(2, 2, glm::vec4(1.0f));
    Image b = a;
    b.at(1, 1).r = 1.4f;
    EXPECT_NEAR(compare_images(a, b).rel_rmse, std::sqrt(0.16 / 12.0), 1e-6);
}

TEST(ImageCompare, MaskSelectsThePixels) {
    const Image a = half_covered();
    Image b = a;
    b.at(12, 3).r += 1.0f;  // on the background by alpha
    EXPECT_EQ(compare_images(a, b).rel_rmse, 0.0);
    Image8 mask(16, 8);
    for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 16; ++x) {
            std::uint8_t* p = mask.at(x, y);
            p[0] = p[1] = p[2] = (x >= 8 ? 255 : 0);
            p[3] = 255;
        }
    }
    const reference::Comparison c = compare_images(a, b, &mask);
    EXPECT_EQ(c.pixels, 8 * 8);
    EXPECT_GT(c.rel_rmse, 0.0);
}

TEST(ImageCompare, MismatchedOrEmptyInputIsAnInputError) {
    const Image a = half_covered(), smaller = half_covered(8, 8);
    EXPECT_THROW(compare_images(a, smaller, nullptr, "x.exr"), InputError);
    Image8 mask(4, 4);
    EXPECT_THROW(compare_images(a, a, &mask), InputError);
    const Image transparent(4, 4, glm::vec4(1.0f, 1.0f, 1.0f, 0.0f));
    EXPECT_THROW(compare_images(transparent, transparent), InputError);
    try {
        compare_images(a, smaller, nullptr, "a.exr vs b.exr");
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), "a.exr vs b.exr: images differ in size (16x8 and 8x8)");
    }
}

TEST(ImageCompare, DiffImageIsBlackWhereEqualAndRedWhereFarOff) {
    const Image a = half_covered();
    Image b = a;
    b.at(1, 1) = glm::vec4(glm::vec3(a.at(1, 1)) * 2.0f, 1.0f);  // 100% off
    const Image8 diff = reference::relative_error_image(a, b);
    EXPECT_EQ(diff.at(0, 0)[0], 0);
    EXPECT_EQ(diff.at(0, 0)[1], 0);
    EXPECT_EQ(diff.at(0, 0)[2], 0);
    EXPECT_EQ(diff.at(1, 1)[0], 255);
    EXPECT_EQ(diff.at(1, 1)[1], 0);
    EXPECT_GT(diff.at(12, 1)[0], 0);  // background: a grey backdrop, not black
    EXPECT_EQ(diff.at(12, 1)[0], diff.at(12, 1)[2]);
}

}  // namespace
}  // namespace envshadow::testing
