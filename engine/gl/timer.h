#pragma once
// GPU time per render pass with GL_TIME_ELAPSED queries. Passes must not nest. Results are read
// back by resolve(), which waits for the GPU; call it after the frame's last pass.
//
// Software rasterisers defer draws to their next flush and date a query by when its commands are
// binned or flushed, not executed: Mesa's llvmpipe (22.3) gives one pass the time of the next, or 0.
// PassTiming::synchronous times passes by the wall clock between glFinish calls instead: exact
// there, at the cost of the overlap between passes (and on a GPU, of its pipelining).
#include <chrono>
#include <string>
#include <string_view>
#include <vector>

#include "core/enum_names.h"
#include "gl/objects.h"

namespace envshadow::gl {

using envshadow::to_string;  // of PassTiming, through its enum_names()

struct PassTime {
    std::string pass;
    double milliseconds = 0.0;
};

enum class PassTiming { queries, synchronous };
inline constexpr EnumName<PassTiming> kPassTimingNames[] = {{PassTiming::queries, "queries"},
                                                            {PassTiming::synchronous, "wait"}};
constexpr std::span<const EnumName<PassTiming>> enum_names(PassTiming) {
    return kPassTimingNames;
}
// The choice that picks by the rasteriser: wait on a software one, queries on a GPU.
inline constexpr std::string_view kAutoPassTiming = "auto";

// kAutoPassTiming, then the names of kPassTimingNames: the command line's choices.
std::vector<std::string> pass_timing_choices();
// One of pass_timing_choices(). Throws UsageError listing them for anything else.
PassTiming parse_pass_timing(std::string_view name, bool software_rasteriser);

class GpuTimer {
public:
    void set_mode(PassTiming mode) { mode_ = mode; }
    PassTiming mode() const { return mode_; }

    void begin(std::string_view pass);
    void end();
    // The passes measured since the last resolve(), in order, then resets for the next frame.
    std::vector<PassTime> resolve();

private:
    struct Entry {
        std::string pass;
        std::size_t query;          // PassTiming::queries
        double milliseconds = 0.0;  // PassTiming::synchronous, set by end()
    };
    std::vector<Query> pool_;
    std::vector<Entry> entries_;
    bool open_ = false;
    PassTiming mode_ = PassTiming::queries;
    std::chrono::steady_clock::time_point started_;
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
