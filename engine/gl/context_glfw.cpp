// A GLFW window with an OpenGL 4.5 core context, for the viewer.
#include <string>

#include "gl/gl.h"  // before GLFW, so GLFW does not pull in a system GL header
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "core/error.h"
#include "gl/context.h"

namespace envshadow::gl::detail {
namespace {

std::string g_last_glfw_error;
void on_glfw_error(int, const char* description) {
    g_last_glfw_error = description;
}

void* glfw_get_proc(const char* name) {
    return reinterpret_cast<void*>(glfwGetProcAddress(name));
}

class GlfwContext final : public Context {
public:
    explicit GlfwContext(GLFWwindow* window) : Context(Backend::window, "GLFW window"), window_(window) {}
    ~GlfwContext() override {
        glfwDestroyWindow(window_);
        glfwTerminate();
    }
    void make_current() override {
        glfwMakeContextCurrent(window_);
        load_gl(&glfw_get_proc);
    }
    void swap_buffers() override { glfwSwapBuffers(window_); }
    void* native_window() const override { return window_; }

private:
    GLFWwindow* window_;
};

}  // namespace

std::unique_ptr<Context> create_glfw_context(const ContextOptions& options) {
    glfwSetErrorCallback(&on_glfw_error);
    if (!display_available())
        throw PlatformError(
            "window: no display (DISPLAY and WAYLAND_DISPLAY are unset); use --backend egl or osmesa "
            "for off-screen rendering, or run under xvfb-run");
    if (!glfwInit()) throw PlatformError("window: glfwInit failed (" + g_last_glfw_error + "); try --backend egl");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, options.debug ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
    GLFWwindow* window = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
    if (!window) {
        const std::string why = g_last_glfw_error;
        glfwTerminate();
        throw PlatformError("window: no OpenGL 4.5 core window (" + why + "); try --backend egl");
    }
    auto result = std::make_unique<GlfwContext>(window);
    result->make_current();
    glfwSwapInterval(options.vsync ? 1 : 0);
    return result;
}

}  // namespace envshadow::gl::detail
