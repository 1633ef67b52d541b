#include "gl/timer.h"

#include <algorithm>

namespace envshadow::gl {

void GpuTimer::begin(std::string_view pass) {
    if (open_) end();
    if (entries_.size() == pool_.size()) pool_.push_back(Query::create(GL_TIME_ELAPSED));
    entries_.push_back({std::string(pass), entries_.size()});
    glBeginQuery(GL_TIME_ELAPSED, pool_[entries_.back().query].id());
    open_ = true;
}

void GpuTimer::end() {
    if (!open_) return;
    glEndQuery(GL_TIME_ELAPSED);
    open_ = false;
}

std::vector<PassTime> GpuTimer::resolve() {
    end();
    std::vector<PassTime> times;
    for (const Entry& e : entries_) {
        GLuint64 ns = 0;
        glGetQueryObjectui64v(pool_[e.query].id(), GL_QUERY_RESULT, &ns);
        // The same pass may be measured in pieces; report their sum.
        auto it = std::find_if(times.begin(), times.end(), [&](const PassTime& t) { return t.pass == e.pass; });
        if (it == times.end()) times.push_back({e.pass, double(ns) * 1e-6});
        else it->milliseconds += double(ns) * 1e-6;
    }
    entries_.clear();
    return times;
}

}  // namespace envshadow::gl
