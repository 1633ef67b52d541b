// Headless EGL: the device platform first (a real GPU, e.g. NVIDIA, with no display), then Mesa's
// surfaceless platform (llvmpipe or a Mesa GPU driver). ENVSHADOW_EGL_PLATFORM=device|surfaceless
// forces one. No surface is made: the context is made current with EGL_NO_SURFACE and renders into
// framebuffer objects.
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "core/error.h"
#include "gl/context.h"

namespace envshadow::gl::detail {
namespace {

std::string egl_error_string(EGLint error) {
    switch (error) {
        case EGL_SUCCESS:
            return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED:
            return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS:
            return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC:
            return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE:
            return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG:
            return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT:
            return "EGL_BAD_CONTEXT";
        case EGL_BAD_DISPLAY:
            return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH:
            return "EGL_BAD_MATCH";
        case EGL_BAD_PARAMETER:
            return "EGL_BAD_PARAMETER";
        default:
            return "EGL error 0x" + std::to_string(error);
    }
}

[[noreturn]] void fail(const std::string& why) {
    throw PlatformError("egl: " + why + "; try --backend osmesa (Mesa's off-screen library) instead");
}

bool has_extension(const char* list, const char* name) {
    if (!list) return false;
    const size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

void* egl_get_proc(const char* name) {
    return reinterpret_cast<void*>(eglGetProcAddress(name));
}

class EglContext final : public Context {
public:
    EglContext(EGLDisplay display, EGLContext context, std::string platform)
        : Context(Backend::egl, std::move(platform)), display_(display), context_(context) {}
    ~EglContext() override {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
        eglTerminate(display_);
    }
    void make_current() override {
        if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
            fail("eglMakeCurrent failed: " + egl_error_string(eglGetError()));
        load_gl(&egl_get_proc);
    }

private:
    EGLDisplay display_;
    EGLContext context_;
};

struct Display {
    EGLDisplay display = EGL_NO_DISPLAY;
    std::string platform;
};

// A hardware EGL device (skipping Mesa's software device, which surfaceless covers).
Display open_device_display(std::string& why) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client, "EGL_EXT_platform_device")) {
        why += "no EGL_EXT_platform_device; ";
        return {};
    }
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_device_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!query_devices || !get_platform_display) {
        why += "EGL device functions missing; ";
        return {};
    }
    EGLint count = 0;
    EGLDeviceEXT devices[16];
    if (!query_devices(16, devices, &count) || count == 0) {
        why += "no EGL devices; ";
        return {};
    }
    const bool any_device = [] {
        const char* forced = std::getenv("ENVSHADOW_EGL_PLATFORM");
        return forced && std::strcmp(forced, "device") == 0;
    }();
    for (EGLint i = 0; i < count; ++i) {
        const char* extensions = query_device_string ? query_device_string(devices[i], EGL_EXTENSIONS) : nullptr;
        if (!any_device && has_extension(extensions, "EGL_MESA_device_software")) continue;
        EGLDisplay display = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (display != EGL_NO_DISPLAY) return {display, "EGL device " + std::to_string(i)};
    }
    why += "no hardware EGL device; ";
    return {};
}

Display open_surfaceless_display(std::string& why) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client, "EGL_MESA_platform_surfaceless")) {
        why += "no EGL_MESA_platform_surfaceless; ";
        return {};
    }
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    EGLDisplay display = get_platform_display
                             ? get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr)
                             : EGL_NO_DISPLAY;
    if (display == EGL_NO_DISPLAY) why += "surfaceless display unavailable; ";
    return {display, "EGL surfaceless"};
}

}  // namespace

std::unique_ptr<Context> create_egl_context(const ContextOptions& options) {
    const char* forced = std::getenv("ENVSHADOW_EGL_PLATFORM");
    const std::string only = forced ? forced : "";
    std::string why;
    for (const std::string& platform : {std::string("device"), std::string("surfaceless")}) {
        if (!only.empty() && only != platform) continue;
        Display d = platform == "device" ? open_device_display(why) : open_surfaceless_display(why);
        if (d.display == EGL_NO_DISPLAY) continue;
        EGLint major = 0, minor = 0;
        if (!eglInitialize(d.display, &major, &minor)) {
            why += d.platform + ": eglInitialize failed (" + egl_error_string(eglGetError()) + "); ";
            continue;
        }
        if (!eglBindAPI(EGL_OPENGL_API)) {
            why += d.platform + ": no desktop OpenGL API; ";
            eglTerminate(d.display);
            continue;
        }
        const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint configs = 0;
        eglChooseConfig(d.display, config_attribs, &config, 1, &configs);
        const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                          4,
                                          EGL_CONTEXT_MINOR_VERSION,
                                          5,
                                          EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                          EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                          EGL_CONTEXT_OPENGL_DEBUG,
                                          options.debug ? EGL_TRUE : EGL_FALSE,
                                          EGL_NONE};
        EGLContext context =
            eglCreateContext(d.display, configs ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, context_attribs);
        if (context == EGL_NO_CONTEXT) {
            why += d.platform + ": no OpenGL 4.5 core context (" + egl_error_string(eglGetError()) + "); ";
            eglTerminate(d.display);
            continue;
        }
        auto result = std::make_unique<EglContext>(d.display, context, d.platform);
        result->make_current();
        return result;
    }
    if (why.size() >= 2) why.resize(why.size() - 2);
    fail(why.empty() ? "no usable platform" : why);
}

}  // namespace envshadow::gl::detail
