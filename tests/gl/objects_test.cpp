// Context-free properties of the GL layer's owners.
#include <type_traits>

#include <gtest/gtest.h>

#include "core/error.h"
#include "gl/objects.h"
#include "gl/timer.h"

namespace envshadow::gl {
namespace {

template <class T>
constexpr bool move_only = !std::is_copy_constructible_v<T> && !std::is_copy_assignable_v<T> &&
                           std::is_nothrow_move_constructible_v<T> && std::is_nothrow_move_assignable_v<T>;

TEST(GlObjects, AreMoveOnly) {
    EXPECT_TRUE(move_only<Buffer>);
    EXPECT_TRUE(move_only<Texture>);
    EXPECT_TRUE(move_only<Framebuffer>);
    EXPECT_TRUE(move_only<VertexArray>);
    EXPECT_TRUE(move_only<Program>);
    EXPECT_TRUE(move_only<Query>);
    EXPECT_TRUE(move_only<Sampler>);
    EXPECT_TRUE(move_only<TransformFeedback>);
}

TEST(GlObjects, EmptyOnesNeedNoContext) {
    // No context exists in this test: constructing, moving and destroying empty objects must not call GL.
    Buffer a;
    Buffer b = std::move(a);
    Texture t;
    Program p;
    TransformFeedback f;
    EXPECT_EQ(b.id(), 0u);
    EXPECT_FALSE(bool(f));
    EXPECT_FALSE(bool(t));
    EXPECT_FALSE(bool(p));
}

TEST(PassTiming, AutoWaitsOnlyOnASoftwareRasteriser) {
    EXPECT_EQ(parse_pass_timing("auto", true), PassTiming::synchronous);
    EXPECT_EQ(parse_pass_timing("auto", false), PassTiming::queries);
    EXPECT_EQ(parse_pass_timing("queries", true), PassTiming::queries);
    EXPECT_EQ(parse_pass_timing("wait", false), PassTiming::synchronous);
    try {
        parse_pass_timing("sometimes", true);
        ADD_FAILURE() << "no error";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("'sometimes' is not one of auto, queries, wait"), std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace envshadow::gl
