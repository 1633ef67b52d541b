#include "render/display.h"

#include <algorithm>
#include <cmath>

#include "render/embedded_shaders.h"
#include "render/shader_interface.h"

namespace envshadow::render {

Display::Display() {
    const gl::ShaderLibrary library = embedded_shaders();
    for (std::size_t i = 0; i < present_programs_.size(); ++i)
        present_programs_[i] = library.build({{GL_VERTEX_SHADER, "present.vert"}, {GL_FRAGMENT_SHADER, "present.frag"}},
                                             {tone_map_define(ToneMap(i))});
    preview_program_ = library.build({{GL_VERTEX_SHADER, "present.vert"}, {GL_FRAGMENT_SHADER, "atlas_preview.frag"}});
    empty_vertex_array_ = gl::VertexArray::create();
}

void Display::present(const gl::Texture& linear, float exposure_stops, ToneMap op, int width, int height) {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, width, height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    present_programs_.at(std::size_t(op)).use();
    glUniform1f(shader::loc::exposure_scale, std::exp2(exposure_stops));
    linear.bind(shader::unit::linear);
    empty_vertex_array_.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

const gl::Texture& Display::atlas_preview(const gl::Texture& atlas_depth, int max_width) {
    const int width = std::min(max_width, atlas_depth.width());
    const int height = std::max(1, atlas_depth.height() * width / std::max(atlas_depth.width(), 1));
    if (!preview_ || preview_.width() != width || preview_.height() != height) {
        preview_ = gl::Texture::create_2d(GL_RGBA8, width, height);
        preview_target_ = gl::Framebuffer::create();
        preview_target_.attach(GL_COLOR_ATTACHMENT0, preview_);
        preview_target_.check_complete("atlas preview");
    }
    GLint previous = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous);
    GLint viewport[4];
    glGetIntegerv(GL_VIEWPORT, viewport);
    preview_target_.bind();
    glViewport(0, 0, width, height);
    glDisable(GL_DEPTH_TEST);
    preview_program_.use();
    atlas_depth.bind(shader::unit::atlas);
    glBindSampler(shader::unit::atlas, 0);
    empty_vertex_array_.bind();
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(previous));
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    return preview_;
}

gl::Texture Display::upload(const Image8& image) {
    gl::Texture texture = gl::Texture::create_2d(GL_RGBA8, image.width, image.height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(texture.id(), 0, 0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    return texture;
}

}  // namespace envshadow::render
