#include "progress.h"

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <utility>

namespace envshadow::app {
namespace {

std::atomic<bool> g_stop_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

void request_stop(int) {
    g_stop_requested.store(true);
}

struct sigaction g_previous_int, g_previous_term;

}  // namespace

ProgressLine::ProgressLine(std::string label, std::string unit, std::FILE* out)
    : ProgressLine(std::move(label), std::move(unit), out, isatty(fileno(out)) != 0) {}

ProgressLine::ProgressLine(std::string label, std::string unit, std::FILE* out, bool enabled)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      out_(out),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

std::string ProgressLine::format(const std::string& label, const std::string& unit, long long done, long long total,
                                 double elapsed_seconds) {
    const double fraction = total > 0 ? std::clamp(double(done) / double(total), 0.0, 1.0) : 0.0;
    char text[256];
    int length = std::snprintf(text, sizeof text, "%s: %d%% (%lld/%lld %s), %.0f s", label.c_str(),
                               int(100.0 * fraction), done, total, unit.c_str(), elapsed_seconds);
    // The rate so far, once there is one; the first rows are no guide.
    if (done > 0 && done < total && length > 0 && std::size_t(length) < sizeof text)
        std::snprintf(text + length, sizeof text - std::size_t(length), ", about %.0f s left",
                      elapsed_seconds * double(total - done) / double(done));
    return text;
}

void ProgressLine::update(long long done, long long total) {
    if (!enabled_) return;
    std::unique_lock lock(mutex_, std::try_to_lock);  // a thread that finds it busy skips its update
    if (!lock.owns_lock()) return;
    const auto now = std::chrono::steady_clock::now();
    if (shown_ && now - last_ < std::chrono::milliseconds(250) && done < total) return;
    last_ = now;
    shown_ = true;
    const std::string text = format(label_, unit_, done, total, std::chrono::duration<double>(now - start_).count());
    std::fprintf(out_, "\r\033[K%s", text.c_str());
    std::fflush(out_);
}

void ProgressLine::finish() {
    std::lock_guard lock(mutex_);
    if (!shown_) return;
    std::fputs("\r\033[K", out_);  // the final report follows on a clean line
    std::fflush(out_);
    shown_ = false;
}

StopOnInterrupt::StopOnInterrupt() {
    g_stop_requested.store(false);
    struct sigaction action {};
    action.sa_handler = request_stop;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &g_previous_int);
    sigaction(SIGTERM, &action, &g_previous_term);
}

StopOnInterrupt::~StopOnInterrupt() {
    sigaction(SIGINT, &g_previous_int, nullptr);
    sigaction(SIGTERM, &g_previous_term, nullptr);
}

const std::atomic<bool>* StopOnInterrupt::flag() {
    return &g_stop_requested;
}

}  // namespace envshadow::app
