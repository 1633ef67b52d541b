#pragma once
// GPU time per render pass with GL_TIME_ELAPSED queries. Passes must not nest. Results are read
// back by resolve(), which waits for the GPU; call it after the frame's last pass.
#include <string>
#include <string_view>
#include <vector>

#include "gl/objects.h"

namespace envshadow::gl {

struct PassTime {
    std::string pass;
    double milliseconds = 0.0;
};

class GpuTimer {
public:
    void begin(std::string_view pass);
    void end();
    // The passes measured since the last resolve(), in order, then resets for the next frame.
    std::vector<PassTime> resolve();

private:
    struct Entry {
        std::string pass;
        std::size_t query;
    };
    std::vector<Query> pool_;
    std::vector<Entry> entries_;
    bool open_ = false;
};

// Begins a pass on construction and ends it on destruction.
class ScopedPass {
public:
    ScopedPass(GpuTimer* timer, std::string_view pass) : timer_(timer) {
        if (timer_) timer_->begin(pass);
    }
    ~ScopedPass() {
        if (timer_) timer_->end();
    }
    ScopedPass(const ScopedPass&) = delete;
    ScopedPass& operator=(const ScopedPass&) = delete;

private:
    GpuTimer* timer_;
};

}  // namespace envshadow::gl
