#include <cmath>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/image_compare.h"

namespace envshadow {
namespace {

Image8 grey(int w, int h, std::uint8_t v) {
    Image8 image(w, h);
    for (size_t i = 0; i < image.rgba.size(); ++i) image.rgba[i] = (i % 4 == 3) ? 255 : v;
    return image;
}

TEST(ImageCompare, IdenticalImagesHaveNoDifference) {
    const ImageDifference d = compare_images(grey(8, 4, 100), grey(8, 4, 100));
    EXPECT_EQ(d.mean, 0.0);
    EXPECT_EQ(d.max, 0);
    EXPECT_EQ(d.differing, 0);
    EXPECT_TRUE(std::isinf(d.psnr));
    EXPECT_TRUE(d.within(Tolerance{}));
}

TEST(ImageCompare, ASmallUniformShiftPassesAndALocalChangeFails) {
    // +1 level everywhere: mean 1, nothing over the per-pixel threshold.
    const ImageDifference shift = compare_images(grey(100, 100, 100), grey(100, 100, 101));
    EXPECT_DOUBLE_EQ(shift.mean, 1.0);
    EXPECT_TRUE(shift.within(Tolerance{}));
    // One 10x10 block changed by 80 levels: 1% of the pixels differ, over the 0.2% allowed.
    Image8 changed = grey(100, 100, 100);
    for (int y = 0; y < 10; ++y)
        for (int x = 0; x < 10; ++x) changed.at(x, y)[1] = 180;
    const ImageDifference local = compare_images(grey(100, 100, 100), changed);
    EXPECT_EQ(local.differing, 100);
    EXPECT_EQ(local.max, 80);
    EXPECT_NEAR(local.mean, 80.0 * 100 / (3.0 * 10000), 1e-9);
    EXPECT_FALSE(local.within(Tolerance{}));
}

TEST(ImageCompare, SizeMismatchIsAnInputError) {
    EXPECT_THROW(compare_images(grey(4, 4, 0), grey(4, 5, 0)), InputError);
}

TEST(ImageCompare, SideBySideHoldsBothImagesAndTheAmplifiedDifference) {
    const Image8 out = side_by_side(grey(2, 2, 10), grey(2, 2, 30));
    ASSERT_EQ(out.width, 6);
    EXPECT_EQ(out.at(0, 0)[0], 10);
    EXPECT_EQ(out.at(2, 0)[0], 30);
    EXPECT_EQ(out.at(4, 0)[0], 80);  // 4 x 20
}

TEST(ImageCompare, HdrRelativeRmseOverTheMask) {
    Image reference(2, 1, glm::vec4(2.0f, 2.0f, 2.0f, 1.0f));
    Image image = reference;
    image.at(0, 0) = glm::vec4(2.2f, 2.2f, 2.2f, 1.0f);  // 10% off
    image.at(1, 0) = glm::vec4(100.0f);                  // masked out
    const HdrDifference d = compare_hdr(reference, image, {true, false});
    EXPECT_EQ(d.pixels, 1);
    EXPECT_NEAR(d.relative_rmse, 0.1, 1e-6);
    EXPECT_NEAR(d.psnr, 10.0 * std::log10(4.0 / 0.04), 1e-4);
}

}  // namespace
}  // namespace envshadow
