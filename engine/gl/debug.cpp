#include "gl/debug.h"

#include <atomic>
#include <mutex>
#include <string>

#include "core/error.h"
#include "core/log.h"
#include "gl/gl.h"

namespace envshadow::gl {
namespace {
std::atomic<int> g_errors{0};
std::mutex g_mutex;
std::string g_last;

void GLAPIENTRY on_debug_message(GLenum, GLenum type, GLuint, GLenum severity, GLsizei length, const GLchar* message,
                                 const void*) {
    const std::string text(message, length > 0 ? size_t(length) : std::char_traits<char>::length(message));
    if (type == GL_DEBUG_TYPE_ERROR) {
        ++g_errors;
        std::lock_guard lock(g_mutex);
        g_last = text;
        log::warn("GL error: " + text);
    } else if (severity == GL_DEBUG_SEVERITY_HIGH || severity == GL_DEBUG_SEVERITY_MEDIUM) {
        log::debug("GL: " + text);
    }
}
}  // namespace

void enable_debug_output() {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(&on_debug_message, nullptr);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_NOTIFICATION, 0, nullptr, GL_FALSE);
}

int debug_error_count() {
    return g_errors;
}

const std::string& last_debug_error() {
    std::lock_guard lock(g_mutex);
    return g_last;
}

void reset_debug_errors() {
    g_errors = 0;
    while (glGetError() != GL_NO_ERROR) {
    }
}

void check_no_errors(const char* where) {
    const GLenum error = glGetError();
    if (error != GL_NO_ERROR) throw PlatformError(std::string(where) + ": GL error 0x" + std::to_string(error));
    if (g_errors > 0) throw PlatformError(std::string(where) + ": " + last_debug_error());
}

}  // namespace envshadow::gl
