// CCVT's last step: whole texels passed across cell borders until neighbouring cells are within a
// texel of each other (sites.h, balance_texels).
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <utility>
#include <vector>

#include "env/sites.h"

namespace envshadow {
namespace {

struct Grid {
    int width, height;
    std::span<const std::uint16_t> cell;

    std::size_t index(int i, int j) const { return std::size_t(j) * std::size_t(width) + std::size_t(i); }
    int wrap(int i) const { return i < 0 ? i + width : i >= width ? i - width : i; }  // i in [-width, 2 width)
    // The cell at (i, j), columns wrapping around the seam; -1 beyond the poles.
    int at(int i, int j) const { return j < 0 || j >= height ? -1 : int(cell[index(wrap(i), j)]); }
    // The 4-neighbours (right, left, below, above); -1 beyond the poles.
    std::array<int, 4> neighbours(int i, int j) const {
        return {at(i + 1, j), at(i - 1, j), at(i, j + 1), at(i, j - 1)};
    }
    bool on_border(std::size_t t) const {
        const int i = int(t % std::size_t(width)), j = int(t / std::size_t(width));
        const int a = int(cell[t]);
        for (int c : neighbours(i, j))
            if (c >= 0 && c != a) return true;
        return false;
    }
    // Whether taking (i, j) out of cell a leaves a's texels around it 4-connected to each other through
    // its 8-neighbourhood (a simple point in digital topology): walking the ring of eight neighbours,
    // the runs of a's texels that touch (i, j) along an edge are at most one. Removing a texel that
    // is not simple would cut its cell in two, locally.
    bool simple(int i, int j, int a) const {
        // Ring order: above, above right, right, below right, below, below left, left, above left.
        static constexpr int di[8] = {0, 1, 1, 1, 0, -1, -1, -1}, dj[8] = {-1, -1, 0, 1, 1, 1, 0, -1};
        bool in[8];
        for (int k = 0; k < 8; ++k) in[k] = at(i + di[k], j + dj[k]) == a;
        int runs_touching = 0, start = -1;
        for (int k = 0; k < 8; ++k)
            if (!in[k]) start = k;
        if (start < 0) return true;  // all eight in a: an inner texel (not on a border anyway)
        // Walk the ring once from just after a texel outside a, counting runs with an edge texel in them.
        bool in_run = false, touches = false;
        for (int step = 1; step <= 8; ++step) {
            const int k = (start + step) % 8;
            if (in[k]) {
                in_run = true;
                touches = touches || k % 2 == 0;  // even positions share an edge with (i, j)
            } else if (in_run) {
                runs_touching += touches;
                in_run = touches = false;
            }
        }
        return runs_touching <= 1;
    }
};

}  // namespace

TexelBalance balance_texels(const ImportanceMap& importance, std::span<std::uint16_t> texel_cell, int cell_count,
                            int max_passes) {
    TexelBalance result;
    const int width = importance.width, height = importance.height;
    if (cell_count < 2 || width < 1 || height < 1) return result;
    const Grid grid{width, height, texel_cell};
    const double least_gap = kCcvtBalanceTolerance * importance.total / cell_count;
    std::vector<double> mass(std::size_t(cell_count), 0.0);
    std::vector<long> texels(std::size_t(cell_count), 0);
    for (std::size_t t = 0; t < texel_cell.size(); ++t) {
        mass[texel_cell[t]] += importance.importance[t];
        ++texels[texel_cell[t]];
    }
    // The texels a pass looks at, in scan order: the border texels (elsewhere a texel has no other cell
    // to go to) that carry importance (the others never move), kept up to date from the texels each pass
    // moved.
    const auto movable = [&](std::size_t t) { return importance.importance[t] > 0.0f && grid.on_border(t); };
    std::vector<std::size_t> candidates, changed;
    for (std::size_t t = 0; t < texel_cell.size(); ++t)
        if (movable(t)) candidates.push_back(t);
    // The next pass's texels as a bit per texel: set, then read in scan order (a sort and merge of the
    // lists cost a quarter of the balancing on studio).
    std::vector<std::uint64_t> next((texel_cell.size() + 63) / 64, 0);
    const auto mark = [&](std::size_t t) { next[t / 64] |= std::uint64_t(1) << (t % 64); };
    for (int pass = 0; pass < max_passes && !candidates.empty(); ++pass) {
        changed.clear();
        for (std::size_t t : candidates) {
            const double w = importance.importance[t];  // > 0: sun texels (left out of the sharing) and black
                                                        // ones are not candidates
            const int i = int(t % std::size_t(width)), j = int(t / std::size_t(width));
            const int a = texel_cell[t];
            if (texels[std::size_t(a)] <= 1) continue;  // a cell keeps its last texel
            int b = -1;
            for (int c : grid.neighbours(i, j))
                if (c >= 0 && c != a &&
                    (b < 0 || mass[std::size_t(c)] < mass[std::size_t(b)] ||
                     (mass[std::size_t(c)] == mass[std::size_t(b)] && c < b)))
                    b = c;
            if (b < 0) continue;
            // Moving w from a to b changes sum (I - share)^2 by 2 w^2 - 2 w (I_a - I_b).
            const double gap = mass[std::size_t(a)] - mass[std::size_t(b)];
            if (!(gap > w && gap > least_gap) || !grid.simple(i, j, a)) continue;
            texel_cell[t] = std::uint16_t(b);
            mass[std::size_t(a)] -= w;
            mass[std::size_t(b)] += w;
            --texels[std::size_t(a)];
            ++texels[std::size_t(b)];
            ++result.moves;
            // The moved texel and its 4-neighbours are the ones whose borders changed.
            changed.push_back(t);
            for (const auto& [i2, j2] :
                 {std::pair{i + 1, j}, std::pair{i - 1, j}, std::pair{i, j + 1}, std::pair{i, j - 1}})
                if (j2 >= 0 && j2 < height) changed.push_back(grid.index(grid.wrap(i2), j2));
        }
        result.passes = pass + 1;
        if (changed.empty()) break;
        // Next pass: this pass's candidates and the changed texels, in scan order, those on a border.
        for (std::size_t t : candidates) mark(t);
        for (std::size_t t : changed) mark(t);
        candidates.clear();
        for (std::size_t w = 0; w < next.size(); ++w)
            for (std::uint64_t bits = std::exchange(next[w], 0); bits != 0; bits &= bits - 1) {
                const std::size_t t = 64 * w + std::size_t(std::countr_zero(bits));
                if (movable(t)) candidates.push_back(t);
            }
    }
    return result;
}

}  // namespace envshadow
