#pragma once
// KHR_debug output. Errors are logged and counted so that tests (and debug builds) can fail on any
// GL error: check `debug_error_count()` or call `check_no_errors()`.
#include <string>

namespace envshadow::gl {

void enable_debug_output();
int debug_error_count();
const std::string& last_debug_error();
void reset_debug_errors();
// Throws PlatformError naming `where` if glGetError() or the debug callback reported an error.
void check_no_errors(const char* where);

}  // namespace envshadow::gl
