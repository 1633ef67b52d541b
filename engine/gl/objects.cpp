#include "gl/objects.h"

#include <cstdio>
#include <string>

#include "core/error.h"

namespace envshadow::gl {

namespace detail {
void destroy_buffer(GLuint id) {
    glDeleteBuffers(1, &id);
}
void destroy_texture(GLuint id) {
    glDeleteTextures(1, &id);
}
void destroy_framebuffer(GLuint id) {
    glDeleteFramebuffers(1, &id);
}
void destroy_vertex_array(GLuint id) {
    glDeleteVertexArrays(1, &id);
}
void destroy_program(GLuint id) {
    glDeleteProgram(id);
}
void destroy_shader(GLuint id) {
    glDeleteShader(id);
}
void destroy_query(GLuint id) {
    glDeleteQueries(1, &id);
}
void destroy_sampler(GLuint id) {
    glDeleteSamplers(1, &id);
}
void destroy_transform_feedback(GLuint id) {
    glDeleteTransformFeedbacks(1, &id);
}
}  // namespace detail

Buffer Buffer::create(std::size_t bytes, const void* data, GLbitfield flags) {
    GLuint id = 0;
    glCreateBuffers(1, &id);
    glNamedBufferStorage(id, GLsizeiptr(bytes ? bytes : 1), data, flags);
    Buffer buffer;
    buffer.name_ = detail::Name<detail::destroy_buffer>(id);
    buffer.size_ = bytes;
    return buffer;
}

void Buffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
    if (bytes) glNamedBufferSubData(id(), GLintptr(offset), GLsizeiptr(bytes), data);
}

void Buffer::upload_resizing(const void* data, std::size_t bytes) {
    if (!*this || bytes > size_)
        *this = create(bytes, data);
    else
        upload(data, bytes);
}

namespace {
// PlatformError unless width x height fits the driver's textures.
void check_texture_size(int width, int height) {
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if (width < 1 || height < 1 || width > max_size || height > max_size)
        throw PlatformError("texture of " + std::to_string(width) + "x" + std::to_string(height) +
                            " exceeds GL_MAX_TEXTURE_SIZE (" + std::to_string(max_size) + ")");
}
}  // namespace

Texture Texture::create_2d(GLenum internal_format, int width, int height, int levels) {
    check_texture_size(width, height);
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    glTextureStorage2D(id, levels, internal_format, width, height);
    Texture texture;
    texture.name_ = detail::Name<detail::destroy_texture>(id);
    texture.width_ = width;
    texture.height_ = height;
    texture.format_ = internal_format;
    texture.set_filter(levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR, GL_LINEAR);
    texture.set_wrap(GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);
    return texture;
}

Texture Texture::create_2d_multisample(GLenum internal_format, int width, int height, int samples) {
    check_texture_size(width, height);
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &id);
    glTextureStorage2DMultisample(id, samples, internal_format, width, height, GL_TRUE);
    Texture texture;
    texture.name_ = detail::Name<detail::destroy_texture>(id);
    texture.width_ = width;
    texture.height_ = height;
    texture.samples_ = samples;
    texture.format_ = internal_format;
    return texture;
}

void Texture::set_filter(GLenum min_filter, GLenum mag_filter) {
    glTextureParameteri(id(), GL_TEXTURE_MIN_FILTER, GLint(min_filter));
    glTextureParameteri(id(), GL_TEXTURE_MAG_FILTER, GLint(mag_filter));
}

void Texture::set_wrap(GLenum s, GLenum t) {
    glTextureParameteri(id(), GL_TEXTURE_WRAP_S, GLint(s));
    glTextureParameteri(id(), GL_TEXTURE_WRAP_T, GLint(t));
}

Framebuffer Framebuffer::create() {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    Framebuffer framebuffer;
    framebuffer.name_ = detail::Name<detail::destroy_framebuffer>(id);
    return framebuffer;
}

void Framebuffer::attach(GLenum attachment, const Texture& texture, int level) {
    glNamedFramebufferTexture(id(), attachment, texture.id(), level);
}

void Framebuffer::check_complete(const std::string& what) const {
    const GLenum status = glCheckNamedFramebufferStatus(id(), GL_FRAMEBUFFER);
    if (status == GL_FRAMEBUFFER_COMPLETE) return;
    char code[16];
    std::snprintf(code, sizeof code, "0x%04X", unsigned(status));
    // An attachment without storage is what a texture too large for the GL's memory leaves.
    const char* reason =
        status == GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT ? ", an attachment without storage: too large?" : "";
    throw PlatformError(what + ": framebuffer incomplete (status " + code + reason + ")");
}

VertexArray VertexArray::create() {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    VertexArray vao;
    vao.name_ = detail::Name<detail::destroy_vertex_array>(id);
    return vao;
}

Sampler Sampler::create(const SamplerDesc& desc) {
    GLuint id = 0;
    glCreateSamplers(1, &id);
    glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, GLint(desc.min_filter));
    glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, GLint(desc.mag_filter));
    glSamplerParameteri(id, GL_TEXTURE_WRAP_S, GLint(desc.wrap_s));
    glSamplerParameteri(id, GL_TEXTURE_WRAP_T, GLint(desc.wrap_t));
    glSamplerParameteri(id, GL_TEXTURE_COMPARE_MODE, GLint(desc.compare_mode));
    glSamplerParameteri(id, GL_TEXTURE_COMPARE_FUNC, GLint(desc.compare_func));
    Sampler sampler;
    sampler.name_ = detail::Name<detail::destroy_sampler>(id);
    return sampler;
}

TransformFeedback TransformFeedback::create() {
    GLuint id = 0;
    glCreateTransformFeedbacks(1, &id);
    TransformFeedback feedback;
    feedback.name_ = detail::Name<detail::destroy_transform_feedback>(id);
    return feedback;
}

Query Query::create(GLenum target) {
    GLuint id = 0;
    glCreateQueries(target, 1, &id);
    Query query;
    query.name_ = detail::Name<detail::destroy_query>(id);
    return query;
}

}  // namespace envshadow::gl
