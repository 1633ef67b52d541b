#pragma once
// The tests' own statement of which texels CCVT may leave out of its equal shares (docs/DESIGN.md §3,
// sites_ccvt): a texel heavier than an equal share of what the cells share, the importance outside
// such texels. A fixed point: total / N where one sun is small, lower where several suns take much.
#include <span>

namespace envshadow::test {

template <class T>
double unsplittable_threshold(std::span<const T> importance, int cells) {
    double total = 0.0;
    for (T v : importance) total += double(v);
    double shared = total, threshold = total / cells;
    for (;;) {
        double heavy = 0.0;
        for (T v : importance) heavy += double(v) > threshold ? double(v) : 0.0;
        if (total - heavy >= shared) return threshold;  // nothing new above the share
        shared = total - heavy;
        threshold = shared / cells;
    }
}

}  // namespace envshadow::test
