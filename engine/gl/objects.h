#pragma once
// Move-only owners of GL object names. Copying is deleted, moving leaves the source empty (id 0),
// an empty object can be made without a context and its destructor does nothing. Objects are made
// with direct state access (glCreate*, GL 4.5).
#include <cstddef>
#include <string>
#include <utility>

#include "gl/gl.h"

namespace envshadow::gl {

namespace detail {
template <void (*Destroy)(GLuint)>
class Name {
public:
    Name() noexcept = default;
    explicit Name(GLuint id) noexcept : id_(id) {}
    Name(const Name&) = delete;
    Name& operator=(const Name&) = delete;
    Name(Name&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
    Name& operator=(Name&& other) noexcept {
        if (this != &other) {
            reset();
            id_ = std::exchange(other.id_, 0);
        }
        return *this;
    }
    ~Name() { reset(); }
    GLuint id() const noexcept { return id_; }

private:
    void reset() noexcept {
        if (id_ != 0) Destroy(id_);  // moved-from or empty: nothing to delete
        id_ = 0;
    }
    GLuint id_ = 0;
};

void destroy_buffer(GLuint id);
void destroy_texture(GLuint id);
void destroy_framebuffer(GLuint id);
void destroy_vertex_array(GLuint id);
void destroy_program(GLuint id);
void destroy_shader(GLuint id);
void destroy_query(GLuint id);
void destroy_sampler(GLuint id);
void destroy_transform_feedback(GLuint id);
}  // namespace detail

class Buffer {
public:
    Buffer() = default;
    // Immutable storage (glNamedBufferStorage); flags e.g. GL_DYNAMIC_STORAGE_BIT.
    static Buffer create(std::size_t bytes, const void* data = nullptr, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);
    GLuint id() const { return name_.id(); }
    std::size_t size() const { return size_; }
    explicit operator bool() const { return id() != 0; }
    void upload(const void* data, std::size_t bytes, std::size_t offset = 0);
    // Grows (recreating the storage) when `bytes` exceeds the current size, then uploads.
    void upload_resizing(const void* data, std::size_t bytes);

private:
    detail::Name<detail::destroy_buffer> name_;
    std::size_t size_ = 0;
};

class Texture {
public:
    Texture() = default;
    static Texture create_2d(GLenum internal_format, int width, int height, int levels = 1);
    // GL_TEXTURE_2D_MULTISAMPLE with `samples` samples per texel at fixed positions (a render target:
    // no filtering or wrapping state; shaders read it through sampler2DMS).
    static Texture create_2d_multisample(GLenum internal_format, int width, int height, int samples);
    GLuint id() const { return name_.id(); }
    int width() const { return width_; }
    int height() const { return height_; }
    int samples() const { return samples_; }  // 1 for a plain 2D texture
    GLenum format() const { return format_; }
    explicit operator bool() const { return id() != 0; }
    void bind(GLuint unit) const { glBindTextureUnit(unit, id()); }
    void set_filter(GLenum min_filter, GLenum mag_filter);
    void set_wrap(GLenum s, GLenum t);

private:
    detail::Name<detail::destroy_texture> name_;
    int width_ = 0, height_ = 0, samples_ = 1;
    GLenum format_ = 0;
};

class Framebuffer {
public:
    Framebuffer() = default;
    static Framebuffer create();
    GLuint id() const { return name_.id(); }
    explicit operator bool() const { return id() != 0; }
    void attach(GLenum attachment, const Texture& texture, int level = 0);
    // Throws PlatformError with the status if the framebuffer is incomplete.
    void check_complete(const std::string& what) const;
    void bind() const { glBindFramebuffer(GL_FRAMEBUFFER, id()); }

private:
    detail::Name<detail::destroy_framebuffer> name_;
};

class VertexArray {
public:
    VertexArray() = default;
    static VertexArray create();
    GLuint id() const { return name_.id(); }
    explicit operator bool() const { return id() != 0; }
    void bind() const { glBindVertexArray(id()); }

private:
    detail::Name<detail::destroy_vertex_array> name_;
};

// A sampler object's parameters; the defaults are GL's own.
struct SamplerDesc {
    GLenum min_filter = GL_NEAREST_MIPMAP_LINEAR;
    GLenum mag_filter = GL_LINEAR;
    GLenum wrap_s = GL_REPEAT;
    GLenum wrap_t = GL_REPEAT;
    // GL_COMPARE_REF_TO_TEXTURE: a depth texture read through it (sampler2DShadow) returns the
    // comparison `reference compare_func texel`, filtered like a colour (GL_LINEAR: 2x2 PCF).
    GLenum compare_mode = GL_NONE;
    GLenum compare_func = GL_LEQUAL;
};

class Sampler {
public:
    Sampler() = default;
    static Sampler create(const SamplerDesc& desc = {});
    GLuint id() const { return name_.id(); }
    explicit operator bool() const { return id() != 0; }
    void bind(GLuint unit) const { glBindSampler(unit, id()); }

private:
    detail::Name<detail::destroy_sampler> name_;
};

class Query {
public:
    Query() = default;
    static Query create(GLenum target);
    GLuint id() const { return name_.id(); }
    explicit operator bool() const { return id() != 0; }

private:
    detail::Name<detail::destroy_query> name_;
};

// A transform feedback object: its own set of capture-buffer bindings, so capturing leaves the
// default object's bindings alone.
class TransformFeedback {
public:
    TransformFeedback() = default;
    static TransformFeedback create();
    GLuint id() const { return name_.id(); }
    explicit operator bool() const { return id() != 0; }
    void attach(GLuint index, const Buffer& buffer) { glTransformFeedbackBufferBase(id(), index, buffer.id()); }
    void bind() const { glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, id()); }

private:
    detail::Name<detail::destroy_transform_feedback> name_;
};

// A linked program. Built by ShaderLibrary (gl/shader.h).
class Program {
public:
    Program() = default;
    explicit Program(GLuint id) : name_(id) {}
    GLuint id() const { return name_.id(); }
    explicit operator bool() const { return id() != 0; }
    void use() const { glUseProgram(id()); }
    GLint uniform_location(const char* name) const { return glGetUniformLocation(id(), name); }

private:
    detail::Name<detail::destroy_program> name_;
};

class Shader {
public:
    Shader() = default;
    explicit Shader(GLuint id) : name_(id) {}
    GLuint id() const { return name_.id(); }

private:
    detail::Name<detail::destroy_shader> name_;
};

}  // namespace envshadow::gl
