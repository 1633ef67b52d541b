// Capacity-constrained relaxation on the sphere (sites_ccvt, env/sites.h).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <queue>
#include <unordered_map>

#include "env/latlong.h"
#include "env/relaxation.h"
#include "env/sites.h"

namespace envshadow {
namespace {

using namespace relaxation;  // what Lloyd and CCVT share (env/relaxation.h)

// Cells' adjacency, weighted by how much importance crosses each border per unit of bias: the integral
// of the importance density along the border over |s_a - s_b|, measured on the texel pairs (p, q) that
// straddle it as 1/2 sum (I_p + I_q) / 2 / |(p - q) . (s_a - s_b)| (horizontal and vertical pairs each
// measure a border once, whatever its slope). The weighted graph Laplacian is the Hessian of the
// capacity problem (de Goes et al. 2012, §4).
class BorderWeights {
public:
    static constexpr int kMaxNeighbours = 48;  // further borders of a cell are dropped (never seen)

    explicit BorderWeights(int cells = 0)
        : cells_(cells), count_(static_cast<size_t>(cells), 0), slots_(static_cast<size_t>(cells) * kMaxNeighbours) {}

    void add(int a, int b, double weight) {
        if (a > b) std::swap(a, b);
        Slot* row = &slots_[size_t(a) * kMaxNeighbours];
        int& n = count_[size_t(a)];
        for (int k = 0; k < n; ++k)
            if (row[k].other == b) {
                row[k].weight += weight;
                return;
            }
        if (n < kMaxNeighbours) row[n++] = {b, weight};
    }
    void add(const BorderWeights& o) {
        o.for_each([&](int a, int b, double w) { add(a, b, w); });
    }
    template <class F>
    void for_each(F&& f) const {  // f(a, b, weight) once per border
        for (int a = 0; a < cells_; ++a)
            for (int k = 0; k < count_[size_t(a)]; ++k) {
                const Slot& slot = slots_[size_t(a) * kMaxNeighbours + size_t(k)];
                f(a, slot.other, slot.weight);
            }
    }
    double mean_degree() const {
        double sum = 0.0;
        for_each([&](int, int, double w) { sum += 2.0 * w; });
        return cells_ > 0 ? sum / cells_ : 0.0;
    }

private:
    struct Slot {
        int other = 0;
        double weight = 0.0;
    };
    int cells_;
    std::vector<int> count_;
    std::vector<Slot> slots_;
};

// How much importance an overfull cell would pass on to its runner-ups if its bias fell by a given
// amount: its border texels counted at the gap between their scores for it and for their runner-up,
// binned by quarter powers of two; reach() interpolates inside a bin.
struct GapHistogram {
    static constexpr int kPerOctave = 4, kBins = 40 * kPerOctave;  // gaps from 2^-40 to 2, and 0
    std::array<double, kBins> mass{};

    static double low(int b) { return b >= kBins - 1 ? 0.0 : std::exp2(-double(b) / kPerOctave); }
    static int bin(double gap) {
        if (!(gap > 0.0)) return kBins - 1;
        return std::clamp(int(std::floor(-std::log2(gap) * kPerOctave)), 0, kBins - 1);
    }
    void add(double gap, double m) { mass[size_t(bin(gap))] += m; }
    // The smallest fall that passes on `amount`, or the largest gap seen when there is not that much.
    double reach(double amount) const {
        double gathered = 0.0, upper = 0.0;
        for (int b = kBins - 1; b >= 0; --b) {
            if (mass[size_t(b)] <= 0.0) continue;
            const double lo = low(b), hi = b == 0 ? 2.0 : low(b - 1);
            if (gathered + mass[size_t(b)] >= amount) return lo + (hi - lo) * (amount - gathered) / mass[size_t(b)];
            gathered += mass[size_t(b)];
            upper = hi;
        }
        return upper;
    }
    GapHistogram& operator+=(const GapHistogram& o) {
        for (int b = 0; b < kBins; ++b) mass[size_t(b)] += o.mass[size_t(b)];
        return *this;
    }
};

// Everything the capacity solver reads from one assignment, in one pass over the texels.
struct CellStatistics {
    std::vector<CellMoments> moments;  // texel by texel, as the cells are
    // Importance with each border texel shared with its runner-up c (the best cell among its four
    // neighbouring texels'): d = score_a - score_c is taken as linear across the texel (a square of the
    // texel's solid angle) and a keeps the fraction where d > 0. These masses change continuously with
    // the biases, as in the continuous problem Newton's method is made for (Kitagawa, Merigot and
    // Thibert 2019).
    std::vector<double> mass;
    BorderWeights borders;
    std::vector<GapHistogram> loss;  // per cell, its border texels at their gap to the runner-up

    explicit CellStatistics(int count = 0)
        : moments(static_cast<size_t>(count)),
          mass(static_cast<size_t>(count), 0.0),
          borders(count),
          loss(static_cast<size_t>(count)) {}
};

CellStatistics cell_statistics(const ImportanceMap& importance, std::span<const std::uint16_t> texel_cell,
                               std::span<const glm::dvec3> sites, std::span<const double> bias) {
    constexpr int kRowsPerChunk = 64;  // 8 chunks at 512 rows: fewer partial sums to allocate and add up
    const int width = importance.width, height = importance.height, count = int(sites.size());
    const int chunks = (height + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<CellStatistics> partial(static_cast<size_t>(chunks), CellStatistics(count));
    auto cell = [&](int i, int j) { return int(texel_cell[size_t(j) * size_t(width) + size_t(i)]); };
    tbb::parallel_for(0, chunks, [&](int chunk) {
        CellStatistics& out = partial[size_t(chunk)];
        for (int j = chunk * kRowsPerChunk; j < std::min(height, (chunk + 1) * kRowsPerChunk); ++j) {
            const double side = std::sqrt(importance.row_solid_angle[size_t(j)]);
            for (int i = 0; i < width; ++i) {
                const size_t t = size_t(j) * size_t(width) + size_t(i);
                const int a = texel_cell[t];
                const double value = importance.importance[t];
                const glm::dvec3 p = importance.directions(i, j);
                out.moments[size_t(a)].add(value, importance.row_solid_angle[size_t(j)], p);
                const int right = i + 1 < width ? i + 1 : 0, left = i > 0 ? i - 1 : width - 1;  // across the seam
                const int neighbours[4] = {cell(right, j), cell(left, j), j + 1 < height ? cell(i, j + 1) : a,
                                           j > 0 ? cell(i, j - 1) : a};
                if (neighbours[0] == a && neighbours[1] == a && neighbours[2] == a && neighbours[3] == a) {
                    out.mass[size_t(a)] += value;  // inside its cell
                    continue;
                }
                // Borders with the texel to the right (across the seam too) and below.
                for (const auto& [i2, j2, b] :
                     {std::tuple{right, j, neighbours[0]}, std::tuple{i, j + 1, neighbours[2]}}) {
                    if (b == a) continue;
                    const size_t q = size_t(j2) * size_t(width) + size_t(i2);
                    const double rate =
                        std::abs(glm::dot(p - importance.directions(i2, j2), sites[size_t(a)] - sites[size_t(b)]));
                    out.borders.add(a, b, 0.25 * (value + importance.importance[q]) / std::max(rate, 1e-12));
                }
                // Runner-up among the neighbouring texels' cells.
                int runner_up = -1;
                double second = -std::numeric_limits<double>::infinity();
                for (int c : neighbours) {
                    if (c == a || c == runner_up) continue;
                    const double score = glm::dot(p, sites[size_t(c)]) + bias[size_t(c)];
                    if (score > second) {
                        second = score;
                        runner_up = c;
                    }
                }
                const double gap = std::max(0.0, glm::dot(p, sites[size_t(a)]) + bias[size_t(a)] - second);
                const glm::dvec3 d = sites[size_t(a)] - sites[size_t(runner_up)];
                const double span = glm::length(d - glm::dot(d, p) * p) * side;  // range of d over the texel
                const double kept = span > 0.0 ? std::min(1.0, 0.5 + gap / span) : 1.0;
                out.mass[size_t(a)] += kept * value;
                out.mass[size_t(runner_up)] += (1.0 - kept) * value;
                out.loss[size_t(a)].add(gap, value);
            }
        }
    });
    CellStatistics total(count);
    for (const CellStatistics& c : partial) {
        for (size_t k = 0; k < size_t(count); ++k) {
            total.moments[k] += c.moments[k];
            total.mass[k] += c.mass[k];
            total.loss[k] += c.loss[k];
        }
        total.borders.add(c.borders);
    }
    return total;
}

// Solves (L + ridge I) x = r by conjugate gradients, L the border Laplacian. The ridge (a hundredth of
// the mean degree) keeps cells with weak borders from taking huge steps (Levenberg-Marquardt).
std::vector<double> solve_laplacian(const BorderWeights& borders, const std::vector<double>& r) {
    const size_t n = r.size();
    const double ridge = 1e-2 * std::max(borders.mean_degree(), 1e-300);
    auto multiply = [&](const std::vector<double>& x, std::vector<double>& y) {
        for (size_t k = 0; k < n; ++k) y[k] = ridge * x[k];
        borders.for_each([&](int a, int b, double w) {
            const double d = w * (x[size_t(a)] - x[size_t(b)]);
            y[size_t(a)] += d;
            y[size_t(b)] -= d;
        });
    };
    std::vector<double> x(n, 0.0), residual = r, direction = r, product(n);
    double rr = 0.0;
    for (double v : residual) rr += v * v;
    const double stop = 1e-20 * rr;
    for (size_t iteration = 0; iteration < 4 * n && rr > stop; ++iteration) {
        multiply(direction, product);
        double dp = 0.0;
        for (size_t k = 0; k < n; ++k) dp += direction[k] * product[k];
        if (!(dp > 0.0)) break;
        const double alpha = rr / dp;
        double next = 0.0;
        for (size_t k = 0; k < n; ++k) {
            x[k] += alpha * direction[k];
            residual[k] -= alpha * product[k];
            next += residual[k] * residual[k];
        }
        for (size_t k = 0; k < n; ++k) direction[k] = residual[k] + (next / rr) * direction[k];
        rr = next;
    }
    return x;
}

double norm(const std::vector<double>& v) {
    double sum = 0.0;
    for (double x : v) sum += x * x;
    return std::sqrt(sum);
}

// Biases that give every cell an equal share of the importance, for fixed sites (the capacity
// constraint of Balzer et al. 2009).
class CapacitySolver {
public:
    CapacitySolver(const ImportanceMap& importance, int count, const Partition& partition, int evaluations)
        : importance_(&importance),
          count_(count),
          partition_(partition),
          texel_cell_(importance.texel_count()),
          evaluations_left_(evaluations) {}

    struct State {
        CellStatistics statistics;
        std::vector<double> excess;  // share - mass per cell
        double variation = 0.0;      // coefficient of variation of the cells' masses
    };

    bool exhausted() const { return evaluations_left_ <= 0; }
    int evaluations_left() const { return evaluations_left_; }

    State evaluate(const std::vector<glm::dvec3>& sites, const std::vector<double>& bias) {
        --evaluations_left_;
        partition_.assign(sites, bias, texel_cell_);
        State state{cell_statistics(*importance_, texel_cell_, sites, bias), {}, 0.0};
        const double share = importance_->total / count_;
        state.excess.assign(size_t(count_), 0.0);
        double squares = 0.0;
        for (int k = 0; k < count_; ++k) {
            state.excess[size_t(k)] = share - state.statistics.mass[size_t(k)];
            squares += state.excess[size_t(k)] * state.excess[size_t(k)];
        }
        state.variation = share > 0.0 ? std::sqrt(squares / count_) / share : std::numeric_limits<double>::infinity();
        return state;
    }

    // Steps from `state` (at `bias`) until the capacity error is under kCcvtCapacityTolerance or
    // `steps` are taken. A Newton step (the border Laplacian as the Hessian of the convex dual whose
    // gradient is mass - target; cells without borders wait) is taken at length alpha = 1, 1/2, ..,
    // kCcvtSmallestStep if no cell falls under half the smallest mass now and |target - mass| shrinks by
    // (1 - alpha / 4) (the damped Newton method of Kitagawa, Merigot and Thibert 2019). Where the linear
    // model fails (a bright edge in reach), every overfull cell instead lowers its bias just enough to
    // pass its excess on to its runner-ups. Stops early when the last kCcvtStallSteps steps together
    // lowered the best variation by less than kCcvtStallGain of it (a stalled solve: on studio each such
    // step spent up to 7 evaluations for a fraction of a point). Leaves `state` and `bias` at the best
    // balance seen.
    void improve(const std::vector<glm::dvec3>& sites, std::vector<double>& bias, State& state, int steps) {
        double floor = std::numeric_limits<double>::infinity();
        for (double m : state.statistics.mass)
            if (m > 0.0) floor = std::min(floor, 0.5 * m);
        double best_variation = state.variation;
        std::vector<double> best_bias = bias;
        State best_state = state;
        std::vector<double> best_after{best_variation};  // the best variation after each step
        auto stalled = [&] {
            return best_after.size() > size_t(kCcvtStallSteps) &&
                   best_variation > (1.0 - kCcvtStallGain) * best_after[best_after.size() - 1 - kCcvtStallSteps];
        };
        for (int s = 0; s < steps && state.variation >= kCcvtCapacityTolerance && !exhausted() && !stalled(); ++s) {
            std::vector<double> step = solve_laplacian(state.statistics.borders, state.excess);
            // A cell without borders (empty at this resolution) has no slope to follow: it waits.
            std::vector<bool> bordered(step.size(), false);
            state.statistics.borders.for_each(
                [&](int a, int b, double) { bordered[size_t(a)] = bordered[size_t(b)] = true; });
            for (size_t k = 0; k < step.size(); ++k)
                if (!bordered[k]) step[k] = 0.0;
            const std::vector<double> start = bias;
            const double error = norm(state.excess);
            bool accepted = false;
            for (double alpha = 1.0; alpha >= kCcvtSmallestStep && !accepted && !exhausted(); alpha *= 0.5) {
                std::vector<double> trial(bias.size());
                for (size_t k = 0; k < bias.size(); ++k) trial[k] = start[k] + alpha * step[k];
                centre(trial);
                State next = evaluate(sites, trial);
                bool kept = true;
                for (size_t k = 0; k < bias.size(); ++k)
                    kept = kept &&
                           (next.statistics.mass[k] >= floor || next.statistics.mass[k] >= state.statistics.mass[k]);
                if (kept && norm(next.excess) <= (1.0 - 0.25 * alpha) * error) {
                    bias = std::move(trial);
                    state = std::move(next);
                    accepted = true;
                }
            }
            if (!accepted && !exhausted()) {
                for (size_t k = 0; k < bias.size(); ++k)
                    if (state.excess[k] < 0.0) bias[k] -= state.statistics.loss[k].reach(-state.excess[k]);
                centre(bias);
                state = evaluate(sites, bias);
            }
            if (state.variation < best_variation) {
                best_variation = state.variation;
                best_bias = bias;
                best_state = state;
            }
            best_after.push_back(best_variation);
        }
        if (best_variation < state.variation) {  // shedding may have made it worse: the best seen stays
            bias = std::move(best_bias);
            state = std::move(best_state);
        }
    }

private:
    static void centre(std::vector<double>& bias) {  // only differences matter
        double mean = 0.0;
        for (double b : bias) mean += b / double(bias.size());
        for (double& b : bias) b -= mean;
    }

    const ImportanceMap* importance_;
    int count_;
    const Partition& partition_;
    std::vector<std::uint16_t> texel_cell_;
    int evaluations_left_;
};

}  // namespace

// The importance CCVT shares out. A texel heavier than an equal share (a sun) cannot be split between
// cells, so it is left out of the sharing: every cell, including the one that happens to hold it,
// takes an equal share of the rest, and a sun's cell carries the sun and one share besides. The share
// is of what is shared, R / N with R the importance outside the heavy texels, so "heavy" is the fixed
// point of texel > R / N (sunrise: four texels of 13% make the share of the rest half of T / N, and
// texels between the two are unsplittable too). Only where such texels are few (a sun's); a map whose
// texels each weigh about a share (as many lights as texels) is shared as it is.
ImportanceMap shareable_importance(const ImportanceMap& importance, int count) {
    std::vector<std::size_t> heavy;
    for (double rest = importance.total;;) {  // the threshold only falls, so this ends
        const double share = rest / count;
        heavy.clear();
        double heavy_sum = 0.0;
        for (std::size_t t = 0; t < importance.texel_count(); ++t)
            if (importance.importance[t] > share) heavy.push_back(t), heavy_sum += importance.importance[t];
        if (importance.total - heavy_sum >= rest || 4 * heavy.size() > std::size_t(count)) break;
        rest = importance.total - heavy_sum;
    }
    if (heavy.empty() || 4 * heavy.size() > std::size_t(count)) return importance;
    ImportanceMap shareable = importance;
    for (std::size_t t : heavy) shareable.importance[t] = 0.0f;
    shareable.total = 0.0;
    for (float v : shareable.importance) shareable.total += v;
    return shareable.total > 0.0 ? shareable : importance;
}

SiteSet sites_ccvt(const ImportanceMap& full_importance, int count, const Partition& partition) {
    const ImportanceMap importance = shareable_importance(full_importance, count);
    SiteSet result;
    result.sites = equal_importance_regions(importance, count);
    result.bias.assign(size_t(count), 0.0);

    // Capacity first at coarse resolutions on blurred importance (a smooth problem, which Newton's method
    // solves well, and cheap to evaluate), then on the map at the working resolution.
    for (const auto& [factor, blur] : kCcvtCoarseLevels) {
        Resolution level = at_resolution(importance, factor, blur, partition.search());
        const int budget = kCcvtEvaluationsPerLevel;
        CapacitySolver capacity(*level.importance, count, *level.partition, budget);
        CapacitySolver::State state = capacity.evaluate(result.sites, result.bias);
        // Sites closer than a texel of this resolution leave cells empty here: move them first.
        for (int round = 0; round < 4 && reseed_empty_cells(result.sites, &result.bias, state.statistics.moments) > 0.0;
             ++round)
            state = capacity.evaluate(result.sites, result.bias);
        capacity.improve(result.sites, result.bias, state, budget);
    }
    // The sites move at a coarser resolution only where its texels are small against a share: a cell
    // must be able to shed or take less than a texel's worth.
    Resolution working = at_resolution(importance, kCcvtWorkingFactor, 0, partition.search());
    if (coarsens(importance, kCcvtWorkingFactor)) {
        double heaviest = 0.0;
        for (float v : working.importance->importance) heaviest = std::max(heaviest, double(v));
        if (heaviest > kCcvtCoarseTexelShare * importance.total / count)
            working = at_resolution(importance, 1, 0, partition.search());
    }
    CapacitySolver capacity(*working.importance, count, *working.partition, kCcvtMaxEvaluations);
    CapacitySolver::State state = capacity.evaluate(result.sites, result.bias);
    capacity.improve(result.sites, result.bias, state, kCcvtEvaluationsPerLevel);

    // Moving the sites can upset the balance where the importance has sharp edges; the best balanced
    // state seen is the one kept.
    SiteSet best = result;
    double best_variation = state.variation;
    for (int iteration = 1; iteration <= kCcvtMaxIterations && !capacity.exhausted(); ++iteration) {
        result.iterations = iteration;
        const std::vector<CellMoments>& cells = state.statistics.moments;
        // Sites towards their centroids, half way and at most kCcvtMoveFraction of the cell's radius, so
        // that the biases stay nearly right; each bias keeps the cell's score at its centroid.
        double relative = 0.0;
        std::vector<glm::dvec3> moved = result.sites;
        std::vector<double> moved_bias = result.bias;
        result.final_movement = 0.0;
        for (int k = 0; k < count; ++k) {
            const glm::dvec3 s = result.sites[size_t(k)];
            const glm::dvec3 c = centroid_direction(cells[size_t(k)], s);
            const double full = angle_between(c, s);
            const double radius =
                std::acos(std::clamp(1.0 - cells[size_t(k)].solid_angle / (2.0 * std::numbers::pi), -1.0, 1.0));
            result.final_movement = std::max(result.final_movement, full);
            relative = std::max(relative, radius > 0.0 ? full / radius : 0.0);
            if (!(full > 0.0)) continue;
            const double step = std::min(0.5 * full, kCcvtMoveFraction * radius);
            const glm::dvec3 axis = glm::normalize(c - s * glm::dot(c, s));
            moved[size_t(k)] = s * std::cos(step) + axis * std::sin(step);
            moved_bias[size_t(k)] += glm::dot(c, s) - glm::dot(c, moved[size_t(k)]);
        }
        if (state.variation <= best_variation || state.variation < kCcvtCapacityTolerance) {
            best = result;
            best_variation = state.variation;
        }
        if (relative < kCcvtRelativeMovementTolerance && state.variation < kCcvtCapacityTolerance) break;
        // Moves that upset the balance (sharp edges in the map) are given up.
        if (state.variation > 2.0 * best_variation + kCcvtCapacityTolerance) break;
        result.sites = std::move(moved);
        result.bias = std::move(moved_bias);
        reseed_empty_cells(result.sites, &result.bias, cells);
        state = capacity.evaluate(result.sites, result.bias);
        capacity.improve(result.sites, result.bias, state, kCcvtNewtonStepsPerIteration);
    }
    if (!(state.variation <= best_variation || state.variation < kCcvtCapacityTolerance)) {
        const int iterations = result.iterations;
        result = best;
        result.iterations = iterations;
    }

    // A last balance at full resolution (the cells are assigned there), with what budget is left.
    CapacitySolver full(importance, count, partition, std::max(kCcvtPolishEvaluations, capacity.evaluations_left()));
    CapacitySolver::State polish = full.evaluate(result.sites, result.bias);
    full.improve(result.sites, result.bias, polish, std::max(kCcvtPolishEvaluations, capacity.evaluations_left()));

    // The power diagram balances the cells only up to the texels along their borders: whole texels
    // are passed across them to even out what is left.
    result.texel_cell.resize(importance.texel_count());
    partition.assign(result.sites, result.bias, result.texel_cell);
    fill_empty_cells(importance, partition, result.sites, result.bias, result.texel_cell);
    balance_texels(importance, result.texel_cell, count);
    return result;
}

}  // namespace envshadow
