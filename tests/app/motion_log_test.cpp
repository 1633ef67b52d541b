// The viewer's motion log (app/viewer/motion_log.h): the frames while the view changed, and how soon a
// full-size frame followed once it stopped.
#include <string>

#include <gtest/gtest.h>

#include "viewer/motion_log.h"

namespace envshadow::app {
namespace {

TEST(MotionLog, FullSizeAgainIsTimedFromTheLastChangingFrame) {
    MotionLog log;
    DrawnFrame moving;
    moving.changing = true;
    moving.scale = 0.5f;
    moving.width = 80;
    moving.height = 45;
    log.record(moving, 100.0, 1.0);
    log.record(moving, 120.0, 1.1);
    DrawnFrame still;
    still.scale = 0.5f;
    log.record(still, 50.0, 1.2);  // still, but not yet at full size
    EXPECT_FALSE(log.full_again);
    still.scale = 1.0f;
    log.record(still, 60.0, 1.5);
    ASSERT_TRUE(log.full_again);
    EXPECT_NEAR(*log.full_again, 0.4, 1e-9);
    log.record(still, 60.0, 2.0);  // the first full-size frame counts, not later ones
    EXPECT_NEAR(*log.full_again, 0.4, 1e-9);
    EXPECT_EQ(log.frame_ms.size(), 2u);
    const std::string line = log.summary(DynamicResolutionOptions{});  // enabled, 100 ms
    EXPECT_NE(line.find("2 frames while the view changed, median 120.0 ms"), std::string::npos) << line;
    EXPECT_NE(line.find("the last at 80x45, 1 sample(s) per pixel, hard shadows; target 100 ms"), std::string::npos)
        << line;
    EXPECT_NE(line.find("full size again 0.40 s after it stopped"), std::string::npos) << line;
}

}  // namespace
}  // namespace envshadow::app
