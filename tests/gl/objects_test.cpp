// Context-free properties of the GL layer's owners.
#include <type_traits>

#include <gtest/gtest.h>

#include "gl/objects.h"

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

}  // namespace
}  // namespace envshadow::gl
