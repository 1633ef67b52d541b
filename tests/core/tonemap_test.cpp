// The tone maps' C++ side against values worked out by hand from the published formulas, and the
// name table the CLI, the viewer and the GLSL defines share.
#include "core/tonemap.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/image.h"

namespace envshadow {
namespace {

TEST(ToneMap, NamesRoundTripAndBadNameIsAUsageError) {
    ASSERT_EQ(enum_value_names<ToneMap>().size(), kToneMapCount);
    for (std::size_t i = 0; i < kToneMapCount; ++i) {  // the table is in the enum's order
        EXPECT_EQ(kToneMapNames[i].value, ToneMap(i));
        EXPECT_EQ(parse_enum<ToneMap>(kToneMapNames[i].name), ToneMap(i));
        EXPECT_EQ(to_string(ToneMap(i)), kToneMapNames[i].name);
    }
    EXPECT_EQ(parse_enum<ToneMap>("neutral"), ToneMap::neutral);
    EXPECT_EQ(tone_map_define(ToneMap::agx), "TONEMAP_AGX");
    EXPECT_THROW(parse_enum<ToneMap>("reinhard"), UsageError);
}

TEST(ToneMap, LinearIsAClamp) {
    const glm::vec3 out = tone_map(ToneMap::linear, {2.0f, 0.25f, -1.0f});
    EXPECT_EQ(out, glm::vec3(1.0f, 0.25f, 0.0f));
}

TEST(ToneMap, AcesIsNarkowiczCurve) {
    // x = 1: (2.51 + 0.03) / (2.43 + 0.59 + 0.14) = 2.54 / 3.16.
    EXPECT_NEAR(tone_map(ToneMap::aces, glm::vec3(1.0f)).g, 2.54f / 3.16f, 1e-6f);
}

TEST(ToneMap, NeutralShiftsDarkColoursAndCompressesHighlights) {
    // Minimum channel above 2 F90 = 0.08 and peak below Ks = 0.76: c - 0.04 exactly.
    const glm::vec3 mid = tone_map(ToneMap::neutral, {0.5f, 0.3f, 0.1f});
    EXPECT_NEAR(mid.r, 0.46f, 1e-6f);
    EXPECT_NEAR(mid.g, 0.26f, 1e-6f);
    EXPECT_NEAR(mid.b, 0.06f, 1e-6f);
    // A grey of 10: p = 9.96, p_n = 1 - 0.24^2 / (9.96 + 1 - 1.52); greys stay grey.
    const glm::vec3 bright = tone_map(ToneMap::neutral, glm::vec3(10.0f));
    EXPECT_NEAR(bright.r, 1.0f - 0.0576f / 9.44f, 1e-5f);
    EXPECT_NEAR(bright.b, bright.r, 1e-6f);
}

TEST(ToneMap, AgxPutsMiddleGreyAtTheSigmoidPivotAndIsMonotonic) {
    // 0.18 encodes to (log2 0.18 + 12.47393) / 16.5 = 20/33, the sigmoid's pivot (0.5), decoded by
    // 2.2: 0.5^2.2 = 0.2176 (the polynomial fit is within 0.005 of the sigmoid there).
    EXPECT_NEAR(tone_map(ToneMap::agx, glm::vec3(0.18f)).g, std::pow(0.5f, 2.2f), 0.01f);
    float previous = -1.0f;
    for (float x = 1e-4f; x < 100.0f; x *= 1.5f) {
        const float y = tone_map(ToneMap::agx, glm::vec3(x)).g;
        EXPECT_GE(y, previous) << x;
        previous = y;
    }
    EXPECT_GT(previous, 0.95f);
}

TEST(ToneMap, Srgb8UsesTheOperatorAndAcesStaysTheDefault) {
    Image image(2, 1);
    image.pixels[0] = {4.0f, 0.5f, 0.0f, 1.0f};
    image.pixels[1] = {0.18f, 0.18f, 0.18f, 1.0f};
    const Image8 aces = tonemap_to_srgb8(image), aces_named = tonemap_to_srgb8(image, 0.0f, ToneMap::aces);
    EXPECT_EQ(aces.rgba, aces_named.rgba);
    const Image8 linear = tonemap_to_srgb8(image, 0.0f, ToneMap::linear);
    EXPECT_EQ(linear.rgba[0], 255);  // 4 clips
    EXPECT_EQ(linear.rgba[1], 188);  // sRGB of 0.5 is 0.7354
    for (ToneMap op : {ToneMap::agx, ToneMap::neutral, ToneMap::linear})
        EXPECT_NE(tonemap_to_srgb8(image, 0.0f, op).rgba, aces.rgba) << to_string(op);
}

}  // namespace
}  // namespace envshadow
