#pragma once
// Long commands on a terminal: one updating progress line, and Ctrl-C that stops cleanly.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace envshadow::app {

// "<label>: 37% (3400/9216 rows), 12 s, about 21 s left" on one line of `out`, rewritten in place
// at most every quarter second, and erased by finish(). Only when `out` is a terminal: logs and
// pipes stay clean. update() may be called from several threads at once.
class ProgressLine {
public:
    ProgressLine(std::string label, std::string unit, std::FILE* out = stderr);
    ProgressLine(std::string label, std::string unit, std::FILE* out, bool enabled);  // tests force it
    ~ProgressLine() { finish(); }
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    void update(long long done, long long total);
    void finish();

    // The text of one update, without the carriage return (for tests).
    static std::string format(const std::string& label, const std::string& unit, long long done, long long total,
                              double elapsed_seconds);

private:
    std::string label_, unit_;
    std::FILE* out_;
    bool enabled_;
    bool shown_ = false;
    std::chrono::steady_clock::time_point start_, last_;
    std::mutex mutex_;
};

// While it lives, SIGINT and SIGTERM only set stop_requested() (the work polls it and throws
// Interrupted); the previous handlers come back when it goes. Writing happens after the work, so a
// stop request never leaves a half-written file.
class StopOnInterrupt {
public:
    StopOnInterrupt();
    ~StopOnInterrupt();
    StopOnInterrupt(const StopOnInterrupt&) = delete;
    StopOnInterrupt& operator=(const StopOnInterrupt&) = delete;

    static const std::atomic<bool>* flag();
};

}  // namespace envshadow::app
