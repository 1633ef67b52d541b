// Contexts on both headless backends: a known image rendered into an FBO and read back, shader
// errors that name file and line, #include working through the real compiler, sampler objects.
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "gl/objects.h"
#include "gl/readback.h"
#include "gl_fixture.h"

namespace envshadow::testing {
namespace {

using ContextTest = GlTest;

TEST_P(ContextTest, IsOpenGL45Core) {
    GLint major = 0, minor = 0, mask = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
    EXPECT_GE(major * 10 + minor, 45);
    EXPECT_TRUE(mask & GL_CONTEXT_CORE_PROFILE_BIT);
    EXPECT_EQ(context().backend(), GetParam());
    EXPECT_FALSE(context().renderer().empty());
}

TEST_P(ContextTest, RendersADepthTestedTriangleIntoAnFbo) {
    constexpr int size = 64;
    gl::Texture color = gl::Texture::create_2d(GL_RGBA32F, size, size);
    gl::Texture depth = gl::Texture::create_2d(GL_DEPTH_COMPONENT32F, size, size);
    gl::Framebuffer fbo = gl::Framebuffer::create();
    fbo.attach(GL_COLOR_ATTACHMENT0, color);
    fbo.attach(GL_DEPTH_ATTACHMENT, depth);
    fbo.check_complete("test");
    gl::Program program =
        project_shaders().build({{GL_VERTEX_SHADER, "test_triangle.vert"}, {GL_FRAGMENT_SHADER, "test_triangle.frag"}});
    gl::VertexArray vao = gl::VertexArray::create();

    fbo.bind();
    glViewport(0, 0, size, size);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    program.use();
    vao.bind();
    // The small triangle is drawn first and is nearer; the large one behind it must not cover it.
    glUniform1f(0, -0.5f);
    glUniform1f(1, 0.5f);
    glUniform3f(2, 1.0f, 1.0f, 1.0f);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glUniform1f(0, 0.5f);
    glUniform1f(1, 1.0f);
    glUniform3f(2, 0.25f, 0.25f, 0.25f);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    const Image image = gl::read_color(fbo, size, size);
    auto sum = [&](int x, int y) {
        const glm::vec4 p = image.at(x, y);
        return p.r + p.g + p.b;
    };
    // Barycentric colours sum to 1 inside a triangle, times its tint.
    EXPECT_NEAR(sum(32, 34), 1.0f, 0.02f);   // centre: the near triangle
    EXPECT_NEAR(sum(10, 56), 0.25f, 0.02f);  // bottom left, outside the small triangle: the far one
    EXPECT_EQ(image.at(2, 2).a, 0.0f);       // top-left corner: cleared
    EXPECT_EQ(image.at(61, 2).a, 0.0f);
    const glm::vec4 bottom_left = image.at(9, 57);  // near vertex 0, which is red
    EXPECT_GT(bottom_left.r, bottom_left.g);
    EXPECT_GT(bottom_left.r, bottom_left.b);
    const glm::vec4 top = image.at(32, 9);  // near vertex 2, which is blue
    EXPECT_GT(top.b, top.r);
}

TEST_P(ContextTest, CompileErrorsNameTheFileAndLine) {
    gl::ShaderLibrary library = project_shaders();
    library.add("broken_part.glsl", "float fine() { return 1.0; }\nfloat broken() { return undefined_name; }\n");
    library.add("broken.frag",
                "#version 450 core\n// comment\n#include \"broken_part.glsl\"\nout vec4 c;\nvoid main() { c = "
                "vec4(fine()); }\n");
    library.add("broken_main.frag", "#version 450 core\nout vec4 c;\n\nvoid main() { c = vec4(nope); }\n");
    try {
        library.build({{GL_VERTEX_SHADER, "test_triangle.vert"}, {GL_FRAGMENT_SHADER, "broken.frag"}});
        FAIL() << "no compile error";
    } catch (const PlatformError& e) {
        EXPECT_NE(std::string(e.what()).find("broken_part.glsl:2:"), std::string::npos) << e.what();
    }
    try {
        library.build({{GL_VERTEX_SHADER, "test_triangle.vert"}, {GL_FRAGMENT_SHADER, "broken_main.frag"}});
        FAIL() << "no compile error";
    } catch (const PlatformError& e) {
        EXPECT_NE(std::string(e.what()).find("broken_main.frag:4:"), std::string::npos) << e.what();
    }
    gl::reset_debug_errors();  // compile failures are reported through KHR_debug too: expected here
}

TEST_P(ContextTest, IncludedFunctionsLinkAndRun) {
    // test_triangle.vert takes test_color() and its uniforms from test_common.glsl.
    gl::Program program =
        project_shaders().build({{GL_VERTEX_SHADER, "test_triangle.vert"}, {GL_FRAGMENT_SHADER, "test_triangle.frag"}});
    EXPECT_NE(program.id(), 0u);
    EXPECT_EQ(program.uniform_location("u_tint"), 2);
}

TEST_P(ContextTest, SamplerTakesItsDescriptionAndDefaultsToGls) {
    auto parameters = [](GLuint sampler) {
        std::vector<GLint> values;
        for (GLenum p : {GL_TEXTURE_MIN_FILTER, GL_TEXTURE_MAG_FILTER, GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T,
                         GL_TEXTURE_COMPARE_MODE, GL_TEXTURE_COMPARE_FUNC}) {
            GLint value = 0;
            glGetSamplerParameteriv(sampler, p, &value);
            values.push_back(value);
        }
        return values;
    };
    GLuint untouched = 0;  // a sampler as GL makes it
    glCreateSamplers(1, &untouched);
    EXPECT_EQ(parameters(gl::Sampler::create().id()), parameters(untouched));
    glDeleteSamplers(1, &untouched);

    const gl::Sampler shadow = gl::Sampler::create({.min_filter = GL_LINEAR,
                                                    .mag_filter = GL_NEAREST,
                                                    .wrap_s = GL_CLAMP_TO_EDGE,
                                                    .wrap_t = GL_MIRRORED_REPEAT,
                                                    .compare_mode = GL_COMPARE_REF_TO_TEXTURE,
                                                    .compare_func = GL_GEQUAL});
    EXPECT_TRUE(bool(shadow));
    EXPECT_EQ(parameters(shadow.id()), (std::vector<GLint>{GL_LINEAR, GL_NEAREST, GL_CLAMP_TO_EDGE, GL_MIRRORED_REPEAT,
                                                           GL_COMPARE_REF_TO_TEXTURE, GL_GEQUAL}));
}

// An incomplete framebuffer names itself and GL's status as the hexadecimal enum the GL headers spell.
TEST_P(ContextTest, AnIncompleteFramebufferSaysWhatAndItsStatusInHex) {
    gl::Framebuffer empty = gl::Framebuffer::create();  // no attachment
    try {
        empty.check_complete("the empty target");
        FAIL() << "no error";
    } catch (const PlatformError& e) {
        EXPECT_NE(std::string(e.what()).find("the empty target: framebuffer incomplete (status 0x8CD7"),
                  std::string::npos)
            << e.what();
    }
}

ENVSHADOW_INSTANTIATE_GL_TEST(ContextTest);

}  // namespace
}  // namespace envshadow::testing
