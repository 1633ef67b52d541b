// Lloyd and capacity-constrained relaxation on the sphere.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <limits>
#include <queue>
#include <cstdio>
#include <cstdlib>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "env/sites.h"

namespace envshadow {
namespace {

double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// Moves every site to its cell's centroid; returns the largest movement (radians).
double move_to_centroids(std::vector<glm::dvec3>& sites, const std::vector<CellMoments>& cells) {
    double movement = 0.0;
    for (size_t k = 0; k < sites.size(); ++k) {
        const glm::dvec3 moved = centroid_direction(cells[k], sites[k]);
        movement = std::max(movement, angle_between(moved, sites[k]));
        sites[k] = moved;
    }
    return movement;
}

// A site whose cell holds no texel is moved next to the site of the cell with the largest
// importance x solid angle (the cell that most needs splitting), a quarter of that cell's radius away.
// Returns the largest jump, so that the relaxation goes on.
double reseed_empty_cells(std::vector<glm::dvec3>& sites, std::vector<double>* bias,
                          const std::vector<CellMoments>& cells) {
    double jump = 0.0;
    std::vector<double> weight(sites.size());
    for (size_t k = 0; k < sites.size(); ++k) weight[k] = cells[k].importance * cells[k].solid_angle;
    for (size_t k = 0; k < sites.size(); ++k) {
        if (cells[k].solid_angle > 0.0) continue;
        const size_t donor = size_t(std::max_element(weight.begin(), weight.end()) - weight.begin());
        weight[donor] *= 0.25;  // the next empty cell picks another donor unless this one still dominates
        const glm::dvec3 d = sites[donor];
        const glm::dvec3 axis = std::abs(d.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
        const glm::dvec3 tangent = glm::normalize(glm::cross(d, axis));
        const double offset = 0.25 * std::sqrt(cells[donor].solid_angle / std::numbers::pi);
        const glm::dvec3 moved = glm::normalize(d * std::cos(offset) + tangent * std::sin(offset));
        jump = std::max(jump, angle_between(moved, sites[k]));
        sites[k] = moved;
        if (bias) (*bias)[k] = (*bias)[donor];
    }
    return jump;
}

// Floyd-Steinberg samples of `weight`, the seed shifting the halftoning's starting error.
std::vector<glm::dvec3> initial_sites(const ImportanceMap& importance, std::span<const float> weight, int count,
                                      std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    return floyd_steinberg_samples(importance, weight, count, 2.0 * uniform01(rng) - 1.0);
}

// Sum over cells of sum I (1 - w . s): the quantisation energy Lloyd's iteration decreases.
double lloyd_energy(const std::vector<glm::dvec3>& sites, const std::vector<CellMoments>& cells) {
    double energy = 0.0;
    for (size_t k = 0; k < sites.size(); ++k)
        energy += cells[k].importance - glm::dot(cells[k].importance_direction, sites[k]);
    return energy;
}

}  // namespace

SiteSet sites_lloyd(const ImportanceMap& importance, int count, std::uint64_t seed, const Partition& partition) {
    // Start at Lloyd's asymptotic site density, sqrt of the importance density (Gersho 1979: rho^(d/(d+2))
    // in d = 2 dimensions), well stratified: weight sqrt(lum) dw = sqrt(I dw).
    std::vector<float> weight(importance.texel_count());
    for (int j = 0; j < importance.height; ++j)
        for (int i = 0; i < importance.width; ++i) {
            const size_t t = size_t(j) * size_t(importance.width) + size_t(i);
            weight[t] = float(std::sqrt(double(importance.importance[t]) * importance.row_solid_angle[size_t(j)]));
        }
    SiteSet result;
    result.sites = initial_sites(importance, weight, count, seed);
    double previous_energy = std::numeric_limits<double>::infinity();
    for (int iteration = 1; iteration <= kLloydMaxIterations; ++iteration) {
        const std::vector<CellMoments> cells = partition.moments(result.sites, {});
        const double energy = lloyd_energy(result.sites, cells);
        result.iterations = iteration;
        // Converged: the last move gained less than kLloydEnergyTolerance of the energy. The sites stay
        // where this partition was computed; final_movement is how far the next step would move them.
        if (previous_energy - energy <= kLloydEnergyTolerance * energy) {
            result.final_movement = 0.0;
            for (size_t k = 0; k < result.sites.size(); ++k)
                result.final_movement =
                    std::max(result.final_movement, angle_between(centroid_direction(cells[k], result.sites[k]), result.sites[k]));
            break;
        }
        previous_energy = energy;
        result.final_movement = move_to_centroids(result.sites, cells);
        result.final_movement = std::max(result.final_movement, reseed_empty_cells(result.sites, nullptr, cells));
        if (result.final_movement == 0.0) break;
    }
    return result;
}

namespace {

struct HeavyTexel {
    double importance;
    std::size_t texel;
};

// Texels that hold more than an equal share of what the cells without such texels share (water
// filling): the k heaviest texels for the largest k < count with I_k > (total - I_1 - .. - I_{k-1}) / (count - k + 1).
std::vector<HeavyTexel> heavy_texels(const ImportanceMap& importance, int count) {
    // The `count` heaviest texels (a min-heap of (importance, texel)).
    using Entry = std::pair<float, std::size_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    for (std::size_t t = 0; t < importance.texel_count(); ++t) {
        const float value = importance.importance[t];
        if (int(heap.size()) < count) heap.push({value, t});
        else if (value > heap.top().first) {
            heap.pop();
            heap.push({value, t});
        }
    }
    std::vector<Entry> top;
    while (!heap.empty()) {
        top.push_back(heap.top());
        heap.pop();
    }
    std::reverse(top.begin(), top.end());  // heaviest first

    std::vector<HeavyTexel> heavy;
    double rest = importance.total;
    for (const Entry& e : top) {
        if (int(heavy.size()) + 1 >= count || !(e.first > rest / (count - int(heavy.size())))) break;
        heavy.push_back({e.first, e.second});
        rest -= e.first;
    }
    return heavy;
}

}  // namespace

namespace {

// How much importance crosses the border of cells a and b per unit of bias: the integral of the
// importance density along the border over |s_a - s_b|, measured on the texel pairs (p, q) that
// straddle it as 1/2 sum (I_p + I_q) / 2 / |(p - q) . (s_a - s_b)| (horizontal and vertical pairs
// each measure the border once, whatever its slope). These weights make the graph Laplacian that is
// the Hessian of the capacity problem (de Goes et al. 2012, §4).
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
        for (int a = 0; a < cells_; ++a)
            for (int k = 0; k < o.count_[size_t(a)]; ++k) {
                const Slot& slot = o.slots_[size_t(a) * kMaxNeighbours + size_t(k)];
                add(a, slot.other, slot.weight);
            }
    }
    template <class F>
    void for_each(F&& f) const {  // f(a, b, weight) once per border
        for (int a = 0; a < cells_; ++a)
            for (int k = 0; k < count_[size_t(a)]; ++k) {
                const Slot& slot = slots_[size_t(a) * kMaxNeighbours + size_t(k)];
                f(a, slot.other, slot.weight);
            }
    }
    std::vector<double> degrees() const {
        std::vector<double> degree(static_cast<size_t>(cells_), 0.0);
        for_each([&](int a, int b, double w) {
            degree[size_t(a)] += w;
            degree[size_t(b)] += w;
        });
        return degree;
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

struct CellStatistics {
    std::vector<CellMoments> moments;
    BorderWeights borders;
};

// One pass over an assignment: the cells' moments and border weights.
CellStatistics cell_statistics(const ImportanceMap& importance, std::span<const std::uint16_t> texel_cell,
                               std::span<const glm::dvec3> sites) {
    constexpr int kRowsPerChunk = 16;
    const int width = importance.width, height = importance.height, count = int(sites.size());
    const int chunks = (height + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<CellStatistics> partial(static_cast<size_t>(chunks),
                                        CellStatistics{std::vector<CellMoments>(sites.size()), BorderWeights(count)});
    auto pair = [&](BorderWeights& w, size_t p, const glm::dvec3& dp, int i2, int j2) {
        const size_t q = size_t(j2) * size_t(width) + size_t(i2);
        const int a = texel_cell[p], b = texel_cell[q];
        if (a == b) return;
        const double rate = std::abs(glm::dot(dp - importance.directions(i2, j2), sites[size_t(a)] - sites[size_t(b)]));
        w.add(a, b, 0.25 * (double(importance.importance[p]) + importance.importance[q]) / std::max(rate, 1e-12));
    };
    tbb::parallel_for(0, chunks, [&](int chunk) {
        CellStatistics& out = partial[size_t(chunk)];
        for (int j = chunk * kRowsPerChunk; j < std::min(height, (chunk + 1) * kRowsPerChunk); ++j)
            for (int i = 0; i < width; ++i) {
                const size_t p = size_t(j) * size_t(width) + size_t(i);
                const glm::dvec3 dp = importance.directions(i, j);
                out.moments[texel_cell[p]].add(importance.importance[p], importance.row_solid_angle[size_t(j)], dp);
                pair(out.borders, p, dp, (i + 1) % width, j);  // across the seam too
                if (j + 1 < height) pair(out.borders, p, dp, i, j + 1);
            }
    });
    CellStatistics total{std::vector<CellMoments>(sites.size()), BorderWeights(count)};
    for (const CellStatistics& c : partial) {
        for (size_t k = 0; k < sites.size(); ++k) total.moments[k] += c.moments[k];
        total.borders.add(c.borders);
    }
    return total;
}

// Solves (L + ridge I) x = r by conjugate gradients, L the border Laplacian. The ridge (a hundredth of
// the mean degree) keeps cells with weak borders from taking huge steps (Levenberg-Marquardt).
[[maybe_unused]] std::vector<double> solve_laplacian(const BorderWeights& borders, const std::vector<double>& r) {
    const size_t n = r.size();
    double mean_degree = 0.0;
    for (double d : borders.degrees()) mean_degree += d / double(n);
    const double ridge = 1e-2 * std::max(mean_degree, 1e-300);
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

// Targets and capacity error of the cells of an assignment. A texel heavier than an equal share (a sun)
// cannot be split, so a cell holding such texels is left free: it keeps what it has, and the other
// cells aim at equal shares of the rest.
class CapacityTargets {
public:
    CapacityTargets(const ImportanceMap& importance, int count)
        : total_(importance.total), count_(count), heavy_(heavy_texels(importance, count)) {}

    // The excess t - m per cell (0 for free cells); returns the coefficient of variation of the
    // sharing cells' importance about their share.
    double excess(std::span<const std::uint16_t> texel_cell, const std::vector<double>& mass,
                  std::vector<double>& excess) const {
        std::vector<bool> free(static_cast<size_t>(count_), false);
        for (const HeavyTexel& h : heavy_) free[texel_cell[h.texel]] = true;
        int sharing = 0;
        double shared = total_;
        for (int k = 0; k < count_; ++k) {
            if (free[size_t(k)]) shared -= mass[size_t(k)];
            else ++sharing;
        }
        const double share = sharing > 0 ? shared / sharing : 0.0;
        excess.assign(size_t(count_), 0.0);
        double squares = 0.0;
        for (int k = 0; k < count_; ++k) {
            if (free[size_t(k)]) continue;
            excess[size_t(k)] = share - mass[size_t(k)];
            squares += excess[size_t(k)] * excess[size_t(k)];
        }
        if (sharing == 0) return 0.0;
        return share > 0.0 ? std::sqrt(squares / sharing) / share : std::numeric_limits<double>::infinity();
    }

private:
    double total_;
    int count_;
    std::vector<HeavyTexel> heavy_;
};

// Keeps every site inside its own power cell (so that no cell empties and no cell drifts away from its
// site): b_c - b_a <= (1 - s_a . s_c) (1 - 1e-3) for every pair, enforced by a few sweeps that split
// each violation between the two biases; then removes the mean (only differences matter).
[[maybe_unused]] void keep_sites_inside(const std::vector<glm::dvec3>& sites, std::vector<double>& bias) {
    const size_t n = sites.size();
    for (int sweep = 0; sweep < 8; ++sweep) {
        bool changed = false;
        for (size_t a = 0; a < n; ++a)
            for (size_t c = 0; c < n; ++c) {
                if (a == c) continue;
                const double gap = (1.0 - glm::dot(sites[a], sites[c])) * (1.0 - 1e-3);
                const double violation = bias[c] - bias[a] - gap;
                if (violation > 0.0) {
                    bias[c] -= 0.5 * violation;
                    bias[a] += 0.5 * violation;
                    changed = true;
                }
            }
        if (!changed) break;
    }
    double mean = 0.0;
    for (double b : bias) mean += b / double(n);
    for (double& b : bias) b -= mean;
}

// How much importance a cell would gain (or lose) if its bias rose (or fell) by a given amount, others
// fixed: every texel is counted with the gap between the scores of its cell and its runner-up (the
// best of the neighbouring cells), under the runner-up (gain) and its own cell (loss). Gaps are
// binned by powers of two; reach() interpolates inside a bin.
struct GapHistogram {
    static constexpr int kPerOctave = 4;
    static constexpr int kBins = 40 * kPerOctave;  // gaps from 2^-40 up to 1, and above
    std::array<double, kBins> mass{};

    // Bin b holds gaps in [lo(b), lo(b - 1)), lo(b) = 2^(-b / kPerOctave).
    static double lo(int b) { return b >= kBins - 1 ? 0.0 : std::exp2(-double(b) / kPerOctave); }
    static int bin(double gap) {
        if (!(gap > 0.0)) return kBins - 1;
        return std::clamp(int(std::floor(-std::log2(gap) * kPerOctave)), 0, kBins - 1);
    }
    void add(double gap, double m) { mass[size_t(bin(gap))] += m; }
    // The smallest bias change that moves `amount` of importance, or the largest gap seen when there is
    // not that much within reach.
    double reach(double amount) const {
        double gathered = 0.0, upper = 0.0;
        for (int b = kBins - 1; b >= 0; --b) {
            if (mass[size_t(b)] <= 0.0) continue;
            const double lo = GapHistogram::lo(b), hi = b == 0 ? 2.0 : GapHistogram::lo(b - 1);
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

struct GapHistograms {
    std::vector<GapHistogram> gain, loss;
};

GapHistograms gap_histograms(const ImportanceMap& importance, std::span<const std::uint16_t> texel_cell,
                             std::span<const glm::dvec3> sites, std::span<const double> bias,
                             const BorderWeights& borders) {
    const size_t count = sites.size();
    std::vector<std::vector<int>> neighbours(count);
    borders.for_each([&](int a, int b, double) {
        neighbours[size_t(a)].push_back(b);
        neighbours[size_t(b)].push_back(a);
    });
    constexpr int kRowsPerChunk = 32;
    const int width = importance.width, height = importance.height;
    const int chunks = (height + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<GapHistograms> partial(static_cast<size_t>(chunks), GapHistograms{std::vector<GapHistogram>(count), std::vector<GapHistogram>(count)});
    tbb::parallel_for(0, chunks, [&](int chunk) {
        GapHistograms& out = partial[size_t(chunk)];
        for (int j = chunk * kRowsPerChunk; j < std::min(height, (chunk + 1) * kRowsPerChunk); ++j)
            for (int i = 0; i < width; ++i) {
                const size_t t = size_t(j) * size_t(width) + size_t(i);
                const int a = texel_cell[t];
                if (neighbours[size_t(a)].empty()) continue;
                const glm::dvec3 p = importance.directions(i, j);
                const double own = glm::dot(p, sites[size_t(a)]) + bias[size_t(a)];
                int runner_up = -1;
                double second = -std::numeric_limits<double>::infinity();
                for (int c : neighbours[size_t(a)]) {
                    const double score = glm::dot(p, sites[size_t(c)]) + bias[size_t(c)];
                    if (score > second) {
                        second = score;
                        runner_up = c;
                    }
                }
                const double gap = std::max(0.0, own - second);
                out.loss[size_t(a)].add(gap, importance.importance[t]);
                out.gain[size_t(runner_up)].add(gap, importance.importance[t]);
            }
    });
    GapHistograms total{std::vector<GapHistogram>(count), std::vector<GapHistogram>(count)};
    for (const GapHistograms& h : partial)
        for (size_t k = 0; k < count; ++k) {
            total.gain[k] += h.gain[k];
            total.loss[k] += h.loss[k];
        }
    return total;
}

// Cell importance with the texels on a border shared between the two cells: the power function
// difference d = score_a - score_c to the runner-up c is taken as linear across the texel (a square of
// the texel's solid angle), and a keeps the fraction of the texel where d > 0. Masses then change
// continuously with the biases, as in the continuous problem Newton's method is made for (Kitagawa,
// Merigot and Thibert 2019); the assignment itself stays texel by texel.
std::vector<double> shared_border_masses(const ImportanceMap& importance, std::span<const std::uint16_t> texel_cell,
                                         std::span<const glm::dvec3> sites, std::span<const double> bias,
                                         const BorderWeights& borders) {
    const size_t count = sites.size();
    std::vector<std::vector<int>> neighbours(count);
    borders.for_each([&](int a, int b, double) {
        neighbours[size_t(a)].push_back(b);
        neighbours[size_t(b)].push_back(a);
    });
    constexpr int kRowsPerChunk = 16;
    const int width = importance.width, height = importance.height;
    const int chunks = (height + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<std::vector<double>> partial(static_cast<size_t>(chunks), std::vector<double>(count, 0.0));
    tbb::parallel_for(0, chunks, [&](int chunk) {
        std::vector<double>& mass = partial[size_t(chunk)];
        for (int j = chunk * kRowsPerChunk; j < std::min(height, (chunk + 1) * kRowsPerChunk); ++j) {
            const double side = std::sqrt(importance.row_solid_angle[size_t(j)]);
            for (int i = 0; i < width; ++i) {
                const size_t t = size_t(j) * size_t(width) + size_t(i);
                const int a = texel_cell[t];
                const double value = importance.importance[t];
                const glm::dvec3 p = importance.directions(i, j);
                const double own = glm::dot(p, sites[size_t(a)]) + bias[size_t(a)];
                int runner_up = -1;
                double second = -std::numeric_limits<double>::infinity();
                for (int c : neighbours[size_t(a)]) {
                    const double score = glm::dot(p, sites[size_t(c)]) + bias[size_t(c)];
                    if (score > second) {
                        second = score;
                        runner_up = c;
                    }
                }
                double kept = 1.0;
                if (runner_up >= 0) {
                    const glm::dvec3 d = sites[size_t(a)] - sites[size_t(runner_up)];
                    const double span = glm::length(d - glm::dot(d, p) * p) * side;  // range of d over the texel
                    if (span > 0.0) kept = std::min(1.0, 0.5 + (own - second) / span);
                    mass[size_t(runner_up)] += (1.0 - kept) * value;
                }
                mass[size_t(a)] += kept * value;
            }
        }
    });
    std::vector<double> total(count, 0.0);
    for (const auto& m : partial)
        for (size_t k = 0; k < count; ++k) total[k] += m[k];
    return total;
}

// The capacity problem for fixed sites: biases with m_a(b) = t_a. They minimise the convex
// F(b) = sum over texels of I max_a (w . s_a + b_a) - sum_a b_a t_a = sum_a (s_a . M_a + b_a (m_a - t_a)),
// whose gradient is m - t and whose Hessian is the border Laplacian (de Goes et al. 2012).
class CapacitySolver {
    static constexpr double kBalanceDamping = 0.5;  // neighbours move the same border from both sides
    static double norm(const std::vector<double>& v) {
        double sum = 0.0;
        for (double x : v) sum += x * x;
        return std::sqrt(sum);
    }

public:
    CapacitySolver(const ImportanceMap& importance, int count, const Partition& partition)
        : importance_(&importance), partition_(partition), targets_(importance, count), texel_cell_(importance.texel_count()) {}
    // Statistics (not the assignment) read this map from now on: a blurred copy for continuation.
    void use_importance(const ImportanceMap& importance) { importance_ = &importance; }

    // The assignment's statistics at (sites, bias), its capacity error (coefficient of variation of the
    // sharing cells' importance) and F.
    struct State {
        CellStatistics statistics;
        std::vector<double> mass;  // shared_border_masses
        std::vector<double> excess;
        double variation = 0.0, dual = 0.0;
    };
    State evaluate(const std::vector<glm::dvec3>& sites, const std::vector<double>& bias) {
        partition_.assign(sites, bias, texel_cell_);
        State state{cell_statistics(*importance_, texel_cell_, sites), {}, {}, 0.0, 0.0};
        if (std::getenv("CCVT_DISCRETE")) { state.mass.resize(sites.size()); for (size_t k=0;k<sites.size();++k) state.mass[k] = state.statistics.moments[k].importance; }
        else state.mass = shared_border_masses(*importance_, texel_cell_, sites, bias, state.statistics.borders);
        state.variation = targets_.excess(texel_cell_, state.mass, state.excess);
        for (size_t a = 0; a < sites.size(); ++a) {
            const CellMoments& m = state.statistics.moments[a];
            state.dual += glm::dot(sites[a], m.importance_direction) - bias[a] * state.excess[a];
        }
        return state;
    }

    // Up to `steps` damped Newton steps from `state` (at `bias`), until the capacity error is under
    // kCcvtCapacityTolerance. Each trial keeps every site inside its own cell (keep_sites_inside) and
    // is taken only if the error |t - m| shrinks by the factor (1 - alpha / 4); alpha halves until it
    // does (after Kitagawa, Merigot and Thibert 2019). Leaves `state` at the final `bias`.
    void improve(const std::vector<glm::dvec3>& sites, std::vector<double>& bias, State& state, int steps) {
        // No trial may leave a cell with less than half the smallest (non-zero) importance of a cell now.
        double floor = std::numeric_limits<double>::infinity();
        for (double m : state.mass)
            if (m > 0.0) floor = std::min(floor, 0.5 * m);
        for (int s = 0; s < steps && state.variation >= kCcvtCapacityTolerance; ++s) {
            // Newton step with the KMT line search.
            const std::vector<double> step = solve_laplacian(state.statistics.borders, state.excess);
            const std::vector<double> start = bias;
            const double error = norm(state.excess);
            bool accepted = false;
            for (double alpha = 1.0; alpha >= 1.0 / 8.0 && !accepted; alpha *= 0.5) {
                std::vector<double> trial(bias.size());
                double mean = 0.0;
                for (size_t k = 0; k < bias.size(); ++k) mean += (start[k] + alpha * step[k]) / double(bias.size());
                for (size_t k = 0; k < bias.size(); ++k) trial[k] = start[k] + alpha * step[k] - mean;
                State next = evaluate(sites, trial);
                bool kept = true;
                for (size_t k = 0; k < bias.size(); ++k)
                    kept = kept && (next.mass[k] >= floor || next.mass[k] >= state.mass[k]);
                if (kept && norm(next.excess) <= (1.0 - 0.25 * alpha) * error) {
                    bias = std::move(trial);
                    state = std::move(next);
                    accepted = true;
                }
            }
            if (!accepted) {
                // Shedding: every overfull cell lowers its bias just enough to pass its excess on to its
                // runner-ups (others fixed). Biases only fall, so it cannot oscillate.
                const GapHistograms gaps = gap_histograms(*importance_, texel_cell_, sites, bias, state.statistics.borders);
                for (size_t k = 0; k < bias.size(); ++k)
                    if (state.excess[k] < 0.0) bias[k] -= gaps.loss[k].reach(-state.excess[k]);
                state = evaluate(sites, bias);
            }
            if (std::getenv("CCVT_DEBUG")) { int empty = 0; for (auto& m : state.statistics.moments) empty += m.solid_angle == 0; std::fprintf(stderr, "  step %d %s var %.4f empty %d\n", s, accepted ? "newton" : "shed", state.variation, empty); }
        }
    }

private:
    const ImportanceMap* importance_;
    const Partition& partition_;
    CapacityTargets targets_;
    std::vector<std::uint16_t> texel_cell_;
};

// A copy of `importance` box-blurred over (2 radius + 1)^2 texels (wrapping around the seam, clamped
// at the poles), scaled back to the same total.
ImportanceMap blurred(const ImportanceMap& importance, int radius) {
    ImportanceMap out = importance;
    const int w = importance.width, h = importance.height;
    std::vector<float> row(importance.importance.size());
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            double sum = 0.0;
            for (int d = -radius; d <= radius; ++d) sum += importance.at(((i + d) % w + w) % w, j);
            row[size_t(j) * size_t(w) + size_t(i)] = float(sum);
        }
    double total = 0.0;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            double sum = 0.0;
            for (int d = -radius; d <= radius; ++d) sum += row[size_t(std::clamp(j + d, 0, h - 1)) * size_t(w) + size_t(i)];
            out.importance[size_t(j) * size_t(w) + size_t(i)] = float(sum);
            total += sum;
        }
    const double scale = total > 0.0 ? importance.total / total : 1.0;
    for (float& v : out.importance) v = float(v * scale);
    return out;
}

}  // namespace

SiteSet sites_ccvt(const ImportanceMap& importance, int count, std::uint64_t seed, const Partition& partition) {
    SiteSet result;
    result.sites = std::getenv("CCVT_FS") ? initial_sites(importance, importance.importance, count, seed) : equal_importance_regions(importance, count);
    result.bias.assign(size_t(count), 0.0);
    CapacitySolver capacity(importance, count, partition);
    CapacitySolver::State state = capacity.evaluate(result.sites, result.bias);
    if (!std::getenv("CCVT_NOBLUR")) {
        for (int radius : {16, 4, 1}) {
            const ImportanceMap soft = blurred(importance, radius);
            capacity.use_importance(soft);
            state = capacity.evaluate(result.sites, result.bias);
            capacity.improve(result.sites, result.bias, state, kCcvtFirstNewtonSteps);
            if (std::getenv("CCVT_DEBUG")) std::fprintf(stderr, "blur %d var %.4f\n", radius, state.variation);
        }
        capacity.use_importance(importance);
    }
    state = capacity.evaluate(result.sites, result.bias);
    capacity.improve(result.sites, result.bias, state, kCcvtFirstNewtonSteps);
    for (int iteration = 1; iteration <= kCcvtMaxIterations; ++iteration) {
        result.iterations = iteration;
        const std::vector<CellMoments>& cells = state.statistics.moments;
        // Sites towards their centroids, half way and at most kCcvtMoveFraction of the cell's radius,
        // so that the biases stay nearly right; each bias keeps the cell's score at its centroid.
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
            if (std::getenv("CCVT_RESET")) { moved[size_t(k)] = c; moved_bias[size_t(k)] = 0.0; continue; }
            const double step = std::min(0.5 * full, kCcvtMoveFraction * radius);
            const glm::dvec3 axis = glm::normalize(c - s * glm::dot(c, s));
            moved[size_t(k)] = s * std::cos(step) + axis * std::sin(step);
            moved_bias[size_t(k)] += glm::dot(c, s) - glm::dot(c, moved[size_t(k)]);
        }
        if (std::getenv("CCVT_DEBUG")) std::fprintf(stderr, "it %d var %.4f move %.3e rel %.3f\n", iteration, state.variation, result.final_movement, relative);
        if (relative < kCcvtRelativeMovementTolerance && state.variation < kCcvtCapacityTolerance) break;
        result.sites = std::move(moved);
        result.bias = std::move(moved_bias);
        reseed_empty_cells(result.sites, &result.bias, cells);
        state = capacity.evaluate(result.sites, result.bias);
        capacity.improve(result.sites, result.bias, state, kCcvtNewtonStepsPerIteration);
    }
    return result;
}

}  // namespace envshadow
