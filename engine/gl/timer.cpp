#include "gl/timer.h"

#include <algorithm>

#include "core/error.h"

namespace envshadow::gl {

std::vector<std::string> pass_timing_choices() {
    std::vector<std::string> choices{std::string(kAutoPassTiming)};
    for (std::string& name : enum_value_names<PassTiming>()) choices.push_back(std::move(name));
    return choices;
}

PassTiming parse_pass_timing(std::string_view name, bool software_rasteriser) {
    if (name == kAutoPassTiming) return software_rasteriser ? PassTiming::synchronous : PassTiming::queries;
    for (const auto& [timing, text] : kPassTimingNames)
        if (text == name) return timing;
    throw UsageError("pass timing '" + std::string(name) + "' is not one of " + std::string(kAutoPassTiming) + ", " +
                     enum_names_list<PassTiming>());
}

void GpuTimer::begin(std::string_view pass) {
    if (open_) end();
    const std::size_t index = entries_.size();
    entries_.push_back({std::string(pass), index});
    if (mode_ == PassTiming::synchronous) {
        glFinish();  // the earlier passes' work is not this pass's
        started_ = std::chrono::steady_clock::now();
    } else {
        if (index == pool_.size()) pool_.push_back(Query::create(GL_TIME_ELAPSED));
        glBeginQuery(GL_TIME_ELAPSED, pool_[index].id());
    }
    open_ = true;
}

void GpuTimer::end() {
    if (!open_) return;
    if (mode_ == PassTiming::synchronous) {
        glFinish();
        entries_.back().milliseconds =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started_).count();
    } else {
        glEndQuery(GL_TIME_ELAPSED);
    }
    open_ = false;
}

std::vector<PassTime> GpuTimer::resolve() {
    end();
    std::vector<PassTime> times;
    for (const Entry& e : entries_) {
        double milliseconds = e.milliseconds;
        if (mode_ == PassTiming::queries) {
            GLuint64 ns = 0;
            glGetQueryObjectui64v(pool_[e.query].id(), GL_QUERY_RESULT, &ns);
            milliseconds = double(ns) * 1e-6;
        }
        // The same pass may be measured in pieces; report their sum.
        auto it = std::find_if(times.begin(), times.end(), [&](const PassTime& t) { return t.pass == e.pass; });
        if (it == times.end())
            times.push_back({e.pass, milliseconds});
        else
            it->milliseconds += milliseconds;
    }
    entries_.clear();
    return times;
}

}  // namespace envshadow::gl
