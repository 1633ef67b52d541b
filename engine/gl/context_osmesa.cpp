// Mesa's off-screen library with a core-profile context (OSMesaCreateContextAttribs). OSMesa wants
// a colour buffer to be current with; we give it a 1x1 one and render into framebuffer objects.
#include <vector>

#include <GL/osmesa.h>

#include "core/error.h"
#include "gl/context.h"

namespace envshadow::gl::detail {
namespace {

void* osmesa_get_proc(const char* name) {
    return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
}

class OsmesaContext final : public Context {
public:
    explicit OsmesaContext(OSMesaContext context) : Context(Backend::osmesa, "OSMesa"), context_(context) {}
    ~OsmesaContext() override { OSMesaDestroyContext(context_); }
    void make_current() override {
        if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, 1, 1))
            throw PlatformError("osmesa: OSMesaMakeCurrent failed; try --backend egl instead");
        load_gl(&osmesa_get_proc);
    }

private:
    OSMesaContext context_;
    std::vector<unsigned char> buffer_ = std::vector<unsigned char>(4);
};

}  // namespace

std::unique_ptr<Context> create_osmesa_context(const ContextOptions&) {
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           4,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           5,
                           0};
    OSMesaContext context = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!context)
        throw PlatformError(
            "osmesa: OSMesaCreateContextAttribs could not make an OpenGL 4.5 core context "
            "(is libosmesa6 a gallium/llvmpipe build?); try --backend egl instead");
    auto result = std::make_unique<OsmesaContext>(context);
    result->make_current();
    return result;
}

}  // namespace envshadow::gl::detail
