// Placeholder until the renderer lands: renders the GL layer's test image (a depth-tested
// coloured triangle) offscreen so that the headless path can be exercised end to end.
#include <string>

#include "commands.h"
#include "core/image.h"
#include "gl/context.h"
#include "gl/objects.h"
#include "gl/readback.h"
#include "gl/shader.h"
#include "glsl/embedded.h"

namespace envshadow::app {
namespace {
struct RenderOptions {
    std::string backend = "egl";
    std::string out;
    int width = 640, height = 360;
};
}  // namespace

Command add_render_command(CLI::App& parent) {
    auto options = std::make_shared<RenderOptions>();
    CLI::App* app = parent.add_subcommand("render", "Render one frame offscreen to PNG and/or EXR");
    app->add_option("--backend", options->backend, "egl or osmesa")->check(CLI::IsMember({"egl", "osmesa"}));
    app->add_option("--out", options->out, "PNG to write")->required();
    app->add_option("--width", options->width, "Image width")->check(CLI::Range(16, 8192));
    app->add_option("--height", options->height, "Image height")->check(CLI::Range(16, 8192));
    app->allow_extras();
    return {app, [options] {
                auto context = gl::create_context(gl::parse_backend(options->backend));
                gl::ShaderLibrary library;
                for (const glsl::File& f : glsl::files()) library.add(f.name, f.source);
                gl::Program program = library.build({{GL_VERTEX_SHADER, "test_triangle.vert"},
                                                     {GL_FRAGMENT_SHADER, "test_triangle.frag"}});
                gl::Texture color = gl::Texture::create_2d(GL_RGBA32F, options->width, options->height);
                gl::Framebuffer fbo = gl::Framebuffer::create();
                fbo.attach(GL_COLOR_ATTACHMENT0, color);
                fbo.check_complete("render");
                gl::VertexArray vao = gl::VertexArray::create();
                fbo.bind();
                glViewport(0, 0, options->width, options->height);
                glClearColor(0.05f, 0.05f, 0.08f, 1.0f);
                glClear(GL_COLOR_BUFFER_BIT);
                program.use();
                vao.bind();
                glUniform1f(0, 0.0f);
                glUniform1f(1, 1.0f);
                glUniform3f(2, 1.0f, 1.0f, 1.0f);
                glDrawArrays(GL_TRIANGLES, 0, 3);
                write_png(options->out, tonemap_to_srgb8(gl::read_color(fbo, options->width, options->height)));
                std::printf("wrote %s (%dx%d, test image; %s)\n", options->out.c_str(), options->width,
                            options->height, context->renderer().c_str());
                return 0;
            }};
}

}  // namespace envshadow::app
