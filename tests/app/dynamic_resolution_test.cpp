// The viewer's dynamic resolution (app/viewer/dynamic_resolution.h) on frame times from a cost
// model: a fixed part (the shadow atlas) plus shading that goes with the pixels, a + b s^2.
#include "viewer/dynamic_resolution.h"

#include <cmath>

#include <gtest/gtest.h>

namespace envshadow::app {
namespace {

// Frame time in ms at scale s: 20 ms of atlas and 380 ms of shading at full size.
double frame_ms(float s) {
    return 20.0 + 380.0 * double(s) * double(s);
}

// Drives `frames` moving frames 50 ms apart from t = 0; returns the time after the last one.
double move(DynamicResolution& resolution, int frames) {
    double t = 0.0;
    for (int i = 0; i < frames; ++i, t += 0.05) {
        const float scale = resolution.scale_for_frame(true, t);
        resolution.record(scale, frame_ms(scale));
    }
    return t;
}

TEST(DynamicResolution, AStillViewIsShadedAtFullSizeHoweverSlow) {
    DynamicResolution resolution;
    for (int i = 0; i < 10; ++i) {
        EXPECT_EQ(resolution.scale_for_frame(false, 1.0 + i), 1.0f);
        resolution.record(1.0f, 2000.0);
        EXPECT_TRUE(resolution.at_full_quality());
    }
}

// The target 100 ms needs 20 + 380 s^2 <= 100, s <= 0.4588: the largest step of 1/16 under it is 7/16.
TEST(DynamicResolution, MovingSettlesOnTheLargestStepThatHoldsTheTarget) {
    DynamicResolution resolution({.enabled = true, .target_ms = 100.0, .settle_seconds = 0.3, .min_scale = 0.25f});
    const double t = move(resolution, 30);
    const float scale = resolution.scale_for_frame(true, t);
    EXPECT_FLOAT_EQ(scale, 7.0f / 16.0f);
    EXPECT_LE(frame_ms(scale), 100.0);
    EXPECT_FALSE(resolution.at_full_quality());
}

TEST(DynamicResolution, FullSizeOnceStillForTheSettleTime) {
    DynamicResolution resolution({.enabled = true, .target_ms = 100.0, .settle_seconds = 0.3, .min_scale = 0.25f});
    const double stopped = move(resolution, 30);
    EXPECT_LT(resolution.scale_for_frame(false, stopped + 0.1), 1.0f) << "still moving, as far as it can tell";
    EXPECT_FALSE(resolution.at_full_quality());
    EXPECT_EQ(resolution.scale_for_frame(false, stopped + 0.31), 1.0f);
    EXPECT_TRUE(resolution.at_full_quality());
    // The next drag starts at the scale it had learned, not at full size.
    EXPECT_FLOAT_EQ(resolution.scale_for_frame(true, stopped + 1.0), 7.0f / 16.0f);
}

TEST(DynamicResolution, AnUnreachableTargetStopsAtTheSmallestScale) {
    DynamicResolution resolution({.enabled = true, .target_ms = 10.0, .settle_seconds = 0.3, .min_scale = 0.25f});
    const double t = move(resolution, 30);
    EXPECT_FLOAT_EQ(resolution.scale_for_frame(true, t), 0.25f);
}

TEST(DynamicResolution, OneSlowFrameHalvesTheScaleAtMost) {
    DynamicResolution resolution({.enabled = true, .target_ms = 1000.0, .settle_seconds = 0.3, .min_scale = 0.0625f});
    EXPECT_EQ(resolution.scale_for_frame(true, 0.0), 1.0f);
    resolution.record(1.0f, 100000.0);  // a shader compile, say: sqrt(1000/100000) would be 0.1
    EXPECT_FLOAT_EQ(resolution.scale_for_frame(true, 0.05), 0.5f);
}

TEST(DynamicResolution, DisabledIsAlwaysFullSize) {
    DynamicResolution resolution({.enabled = false, .target_ms = 10.0, .settle_seconds = 0.3, .min_scale = 0.25f});
    const double t = move(resolution, 10);
    EXPECT_EQ(resolution.scale_for_frame(true, t), 1.0f);
    EXPECT_TRUE(resolution.at_full_quality());
}

}  // namespace
}  // namespace envshadow::app
