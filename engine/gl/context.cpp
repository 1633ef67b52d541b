#include "gl/context.h"

#include <cstdlib>

#include "core/error.h"
#include "gl/debug.h"
#include "gl/gl.h"

namespace envshadow::gl {

std::vector<std::string> headless_backend_names() {
    std::vector<std::string> names;
    for (const auto& [backend, name] : kBackendNames)
        if (backend != Backend::window) names.emplace_back(name);
    return names;
}

Backend parse_backend(std::string_view name) {
    if (name == "glfw") return Backend::window;
    for (const auto& [backend, text] : kBackendNames)
        if (text == name) return backend;
    throw UsageError("unknown backend '" + std::string(name) + "' (expected " + enum_names_list<Backend>() + ")");
}

bool display_available() {
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    return (x11 && *x11) || (wayland && *wayland);
}

Backend default_backend(bool wants_window) {
    return wants_window && display_available() ? Backend::window : Backend::egl;
}

namespace {
// The glad entry points are process-wide. OSMesa's functions are not glvnd's, so switching between
// an OSMesa context and an EGL/GLX one must reload them.
void* (*g_loaded_with)(const char*) = nullptr;
}  // namespace

void Context::load_gl(void* (*get_proc)(const char*)) {
    if (g_loaded_with == get_proc) return;
    if (!gladLoadGL(reinterpret_cast<GLADloadfunc>(get_proc)))
        throw PlatformError(std::string(to_string(backend_)) + ": could not load the OpenGL 4.5 entry points");
    g_loaded_with = get_proc;
}

std::string Context::renderer() const {
    const GLubyte* s = glGetString(GL_RENDERER);
    return s ? reinterpret_cast<const char*>(s) : "unknown";
}

bool Context::is_software() const {
    const std::string name = renderer();
    for (const char* software : {"llvmpipe", "softpipe", "SWR", "Software Rasterizer"})
        if (name.find(software) != std::string::npos) return true;
    return false;
}

std::string Context::version() const {
    const GLubyte* s = glGetString(GL_VERSION);
    return s ? reinterpret_cast<const char*>(s) : "unknown";
}

std::unique_ptr<Context> create_context(Backend backend, const ContextOptions& options) {
    std::unique_ptr<Context> context;
    switch (backend) {
        case Backend::window:
            context = detail::create_glfw_context(options);
            break;
        case Backend::egl:
            context = detail::create_egl_context(options);
            break;
        case Backend::osmesa:
            context = detail::create_osmesa_context(options);
            break;
    }
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 45)
        throw PlatformError(std::string(to_string(backend)) + ": got OpenGL " + std::to_string(major) + "." +
                            std::to_string(minor) + " (" + context->renderer() + "), 4.5 core is needed");
    if (options.debug) enable_debug_output();
    return context;
}

std::vector<BackendProbe> probe_backends() {
    std::vector<BackendProbe> probes;
    for (Backend b : {Backend::egl, Backend::osmesa}) {
        BackendProbe probe{b, false, {}};
        try {
            auto context = create_context(b, ContextOptions{64, 64});
            probe.available = true;
            probe.detail = context->renderer() + ", OpenGL " + context->version() + " (" + context->platform() + ")";
        } catch (const std::exception& e) {
            probe.detail = e.what();
        }
        probes.push_back(std::move(probe));
    }
    probes.push_back(BackendProbe{Backend::window, display_available(),
                                  display_available() ? "display present" : "no DISPLAY or WAYLAND_DISPLAY"});
    return probes;
}

}  // namespace envshadow::gl
