#include <gtest/gtest.h>

#include "bench_stats.h"
#include "core/error.h"

namespace envshadow::app {
namespace {

TEST(BenchStats, MedianAndP95OfKnownSamples) {
    // 1..100 shuffled: median 50.5, p95 = 95.05 by linear interpolation.
    std::vector<double> samples;
    for (int i = 100; i >= 1; --i) samples.push_back(i);
    const TimeSummary s = summarize(samples);
    EXPECT_DOUBLE_EQ(s.median, 50.5);
    EXPECT_NEAR(s.p95, 95.05, 1e-9);
    EXPECT_DOUBLE_EQ(s.mean, 50.5);
    EXPECT_DOUBLE_EQ(s.min, 1.0);
    EXPECT_DOUBLE_EQ(s.max, 100.0);
}

TEST(BenchStats, OddCountMedianIsTheMiddleSample) {
    EXPECT_DOUBLE_EQ(summarize({3.0, 1.0, 2.0}).median, 2.0);
    EXPECT_DOUBLE_EQ(summarize({}).median, 0.0);
}

TEST(BenchStats, ParsesSweeps) {
    const auto lights = parse_sweep("lights=16,32,256");
    ASSERT_EQ(lights.size(), 3u);
    EXPECT_EQ(lights[2].lights, 256);
    EXPECT_EQ(lights[0].label, "lights=16");
    const auto res = parse_sweep("resolution=640x360,1920x1080");
    ASSERT_EQ(res.size(), 2u);
    EXPECT_EQ(res[1].width, 1920);
    EXPECT_EQ(res[1].height, 1080);
    EXPECT_EQ(parse_sweep("tile=512")[0].tile, 512);
}

TEST(BenchStats, RejectsBadSweeps) {
    EXPECT_THROW(parse_sweep("lights"), UsageError);
    EXPECT_THROW(parse_sweep("colour=1"), UsageError);
    EXPECT_THROW(parse_sweep("lights=16,abc"), UsageError);
    EXPECT_THROW(parse_sweep("lights=-4"), UsageError);
    EXPECT_THROW(parse_sweep("resolution=640"), UsageError);
}

}  // namespace
}  // namespace envshadow::app
