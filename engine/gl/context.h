#pragma once
// One interface for the three ways envshadow gets an OpenGL 4.5 core context:
//   window  GLFW (the viewer), needs a display;
//   egl     EGL without a display: the device platform (NVIDIA, or any GPU) or Mesa's surfaceless
//           platform; rendering goes to framebuffer objects;
//   osmesa  Mesa's off-screen library, core profile: a second headless path.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/enum_names.h"

namespace envshadow::gl {

using envshadow::to_string;  // of the enums below, through their enum_names()

enum class Backend { window, egl, osmesa };
inline constexpr EnumName<Backend> kBackendNames[] = {
    {Backend::window, "window"}, {Backend::egl, "egl"}, {Backend::osmesa, "osmesa"}};
constexpr std::span<const EnumName<Backend>> enum_names(Backend) {
    return kBackendNames;
}
// The backends that need no display (all but window): the choices of the headless commands.
std::vector<std::string> headless_backend_names();

// A name of kBackendNames (or "glfw" for window). Throws UsageError listing the names on anything else.
Backend parse_backend(std::string_view name);
// True when an X11 or Wayland display is available for the window backend.
bool display_available();

struct ContextOptions {
    int width = 1280;  // window size; headless contexts render into FBOs of any size
    int height = 720;
    bool debug = false;   // KHR_debug output; GL errors are counted (see gl/debug.h)
    bool visible = true;  // window backend only
    bool vsync = false;   // window backend only
    std::string title = "envshadow";
};

class Context {
public:
    virtual ~Context() = default;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    Backend backend() const { return backend_; }
    // Makes the context current on this thread and points the GL loader at its functions.
    virtual void make_current() = 0;
    virtual void swap_buffers() {}
    // GLFWwindow* for the window backend, nullptr otherwise.
    virtual void* native_window() const { return nullptr; }

    // GL_RENDERER, GL_VERSION and a short description of the platform ("EGL device 0", ...).
    std::string renderer() const;
    std::string version() const;
    // Mesa's llvmpipe, softpipe or another rasteriser on the CPU (GL_RENDERER says so).
    bool is_software() const;
    const std::string& platform() const { return platform_; }

protected:
    Context(Backend backend, std::string platform) : backend_(backend), platform_(std::move(platform)) {}
    // Loads the GL entry points through `get_proc` if the last loaded context was of another kind.
    void load_gl(void* (*get_proc)(const char*));

private:
    Backend backend_;
    std::string platform_;
};

// Creates and makes current a context of the given backend. Throws PlatformError with a message
// that names the backend, says why it failed and which backend to try instead.
std::unique_ptr<Context> create_context(Backend backend, const ContextOptions& options = {});

// Backend to use when none is given: window for the viewer when a display exists, else egl.
Backend default_backend(bool wants_window);

// For `envshadow --version`: tries each headless backend and reports renderer or failure.
struct BackendProbe {
    Backend backend;
    bool available = false;
    std::string detail;  // renderer string, or why it failed
};
std::vector<BackendProbe> probe_backends();

namespace detail {
std::unique_ptr<Context> create_egl_context(const ContextOptions& options);
std::unique_ptr<Context> create_osmesa_context(const ContextOptions& options);
std::unique_ptr<Context> create_glfw_context(const ContextOptions& options);
}  // namespace detail

}  // namespace envshadow::gl
