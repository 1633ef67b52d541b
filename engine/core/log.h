#pragma once
// Progress and diagnostics go to stderr so that stdout stays machine-readable (tables, JSON).
#include <string_view>

namespace envshadow::log {

enum class Level { quiet, info, debug };

void set_level(Level level);
Level level();

void info(std::string_view message);
void debug(std::string_view message);
void warn(std::string_view message);

}  // namespace envshadow::log
