#include "render/gpu_texture.h"

#include <algorithm>
#include <bit>
#include <cstdint>

namespace envshadow::render {
namespace {

GLenum gl_wrap(TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::clamp_to_edge:
            return GL_CLAMP_TO_EDGE;
        case TextureWrap::mirrored_repeat:
            return GL_MIRRORED_REPEAT;
        case TextureWrap::repeat:
        default:
            return GL_REPEAT;
    }
}

}  // namespace

gl::Texture upload_material_texture(const MaterialTexture& texture) {
    const TextureImage& image = *texture.image;
    const auto largest = std::uint32_t(std::max(image.width, image.height));
    const int levels = std::bit_width(largest);  // down to 1x1
    gl::Texture out =
        gl::Texture::create_2d(texture.srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, image.width, image.height, levels);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(out.id(), 0, 0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    glGenerateTextureMipmap(out.id());
    out.set_filter(GL_LINEAR_MIPMAP_LINEAR, texture.nearest ? GL_NEAREST : GL_LINEAR);
    out.set_wrap(gl_wrap(texture.wrap_s), gl_wrap(texture.wrap_t));
    return out;
}

gl::Texture white_texture() {
    gl::Texture out = gl::Texture::create_2d(GL_SRGB8_ALPHA8, 1, 1);
    const std::uint8_t white[4] = {255, 255, 255, 255};
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(out.id(), 0, 0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, white);
    return out;
}

}  // namespace envshadow::render
