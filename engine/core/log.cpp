#include "core/log.h"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace envshadow::log {
namespace {
std::atomic<Level> g_level{Level::info};
std::mutex g_mutex;

void write(const char* prefix, std::string_view message) {
    std::lock_guard lock(g_mutex);
    std::fprintf(stderr, "%s%.*s\n", prefix, static_cast<int>(message.size()), message.data());
}
}  // namespace

void set_level(Level level_) {
    g_level = level_;
}
Level level() {
    return g_level;
}

void info(std::string_view message) {
    if (g_level >= Level::info) write("", message);
}
void debug(std::string_view message) {
    if (g_level >= Level::debug) write("debug: ", message);
}
void warn(std::string_view message) {
    write("warning: ", message);
}

}  // namespace envshadow::log
