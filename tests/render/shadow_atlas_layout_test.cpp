// The shadow atlas's tiling and the per-light orthographic fit, without GL.
#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "env/cells.h"
#include "render/shadow_atlas_layout.h"

namespace envshadow::render {
namespace {

TEST(AtlasLayout, DesignsExampleIs16By8TilesIn4096By2048) {
    const AtlasLayout layout = plan_atlas(128, 256, 16384);
    EXPECT_EQ(layout.columns, 16);
    EXPECT_EQ(layout.rows, 8);
    EXPECT_EQ(layout.width(), 4096);
    EXPECT_EQ(layout.height(), 2048);
    EXPECT_EQ(layout.bytes(16), 4096u * 2048u * 2u);  // 16 MiB; the paper's 100 maps of 256^2: 13 MB
    EXPECT_EQ(layout.bytes(32), 4096u * 2048u * 4u);
}

TEST(AtlasLayout, EveryTileFitsAndNoneIsWasted) {
    for (int tiles = 1; tiles <= kMaxLights; ++tiles) {
        const AtlasLayout layout = plan_atlas(tiles, 128, 16384);
        EXPECT_GE(layout.columns * layout.rows, tiles);
        EXPECT_LT(layout.columns * (layout.rows - 1), tiles) << "a whole empty row for " << tiles;
    }
    EXPECT_EQ(plan_atlas(1, 256, 16384).width(), 256);
}

TEST(AtlasLayout, ShrinksTilesWhenTheAtlasExceedsTheLimit) {
    const AtlasLayout layout = plan_atlas(256, 2048, 16384);  // 16 x 16 tiles of 2048^2 = 32768^2
    EXPECT_EQ(layout.requested_tile_size, 2048);
    EXPECT_EQ(layout.tile_size, 1024);
    EXPECT_LE(layout.width(), 16384);
    EXPECT_THROW(plan_atlas(256, 256, 1024), PlatformError);  // even 128^2 tiles need 2048
}

TEST(OrthographicFit, PointsLandInsideTheMarginAndTouchIt) {
    const std::vector<glm::vec3> points = {{-1, 0, -1}, {1, 0, -1}, {-1, 2, 1}, {1, 2, 1}, {0.3f, 1.5f, 0.2f}};
    const LightFrame frame = light_frame(glm::normalize(glm::vec3(0.3f, 1.0f, 0.5f)));
    const int tile = 256;
    const float margin = 3.0f;
    const OrthographicFit fit = fit_orthographic(frame, points, tile, margin);
    const float limit = 1.0f - 2.0f * margin / float(tile);
    glm::vec3 lo(10.0f), hi(-10.0f);
    for (const glm::vec3& p : points) {
        const glm::vec4 c = fit.clip_from_world * glm::vec4(p, 1.0f);
        EXPECT_FLOAT_EQ(c.w, 1.0f);
        lo = glm::min(lo, glm::vec3(c));
        hi = glm::max(hi, glm::vec3(c));
    }
    // Tight: the extreme points sit on the margin in x and y, inside (-1, 1) in depth.
    EXPECT_NEAR(lo.x, -limit, 1e-5f);
    EXPECT_NEAR(hi.x, limit, 1e-5f);
    EXPECT_NEAR(lo.y, -limit, 1e-5f);
    EXPECT_NEAR(hi.y, limit, 1e-5f);
    EXPECT_GT(lo.z, -1.0f);
    EXPECT_LT(hi.z, 1.0f);
    EXPECT_GT(lo.z, -0.999f);  // not far from tight: 1% widening
    EXPECT_LT(lo.z, -0.97f);
    EXPECT_GT(fit.texel_world, 0.0f);
    EXPECT_GT(fit.depth_range, 0.0f);
}

TEST(OrthographicFit, NearerTheLightIsSmallerDepth) {
    const glm::vec3 toward(0.0f, 1.0f, 0.0f);  // light overhead: higher points are nearer
    const std::vector<glm::vec3> points = {{0, 0, 0}, {1, 1, 1}};
    const OrthographicFit fit = fit_orthographic(light_frame(toward), points, 128, 3.0f);
    const float low = (fit.clip_from_world * glm::vec4(0.5f, 0.0f, 0.5f, 1.0f)).z;
    const float high = (fit.clip_from_world * glm::vec4(0.5f, 1.0f, 0.5f, 1.0f)).z;
    EXPECT_LT(high, low);
    // The depth range is the points' extent along the light (1 m), widened by 1% and a little.
    EXPECT_NEAR(fit.depth_range, 1.01f, 0.01f);
}

TEST(OrthographicFit, EdgeOnPlaneDoesNotCollapse) {
    const std::vector<glm::vec3> points = {{-1, 0, -1}, {1, 0, -1}, {-1, 0, 1}, {1, 0, 1}};
    const OrthographicFit fit = fit_orthographic(light_frame({1.0f, 0.0f, 0.0f}), points, 128, 3.0f);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) EXPECT_TRUE(std::isfinite(fit.clip_from_world[c][r]));
}

TEST(LightFrame, IsOrthonormalAndRightHandedForEveryDirection) {
    for (const glm::vec3 d : {glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::vec3(1, 0, 0), glm::vec3(0.1f, 0.99f, 0.0f),
                              glm::vec3(-0.3f, -0.2f, 0.9f)}) {
        const LightFrame f = light_frame(d);
        EXPECT_NEAR(glm::dot(f.toward, glm::normalize(d)), 1.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(f.right, f.up), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(f.right, f.toward), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::length(f.right), 1.0f, 1e-6f);
        EXPECT_NEAR(glm::length(f.up), 1.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(glm::cross(f.right, f.up), f.toward), 1.0f, 1e-6f);
    }
}

}  // namespace
}  // namespace envshadow::render
