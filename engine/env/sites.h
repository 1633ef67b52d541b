#pragma once
// The five ways of placing sites on the sphere (docs/DESIGN.md §3). Each returns sites (and, for CCVT, the
// power-diagram biases); decompose() then assigns texels to the nearest site and integrates the cells.
#include <cstdint>
#include <glm/vec3.hpp>
#include <random>
#include <span>
#include <utility>
#include <vector>

#include "env/importance.h"
#include "env/nearest_site.h"

namespace envshadow {

struct SiteSet {
    std::vector<glm::dvec3> sites;  // unit vectors
    std::vector<double> bias;       // empty, or per site (nearest_site.h): CCVT's power weights / 2
    int iterations = 0;             // relaxation iterations run (Lloyd, CCVT), at every resolution
    int coarse_iterations = 0;      // of those, the ones run at a lower resolution (Lloyd)
    double final_movement = 0.0;    // largest site movement of the last iteration, radians
    // Empty, or the texel -> cell assignment the method settled on (CCVT: the power diagram of the sites
    // and biases, then balance_texels); decompose() assigns texels to the nearest site where it is empty.
    std::vector<std::uint16_t> texel_cell;
};

// Uniform double in [0, 1) from 53 random bits (the same on every standard library).
double uniform01(std::mt19937_64& rng);

// `count` distinct texels drawn with probability proportional to importance (inverse CDF); a texel drawn
// twice is drawn again. Where fewer texels than that carry importance, the rest are drawn in proportion
// to solid angle. Returns texel indices (j * width + i) in the order drawn. Requires count <= texels.
std::vector<std::size_t> sample_distinct_texels(const ImportanceMap& importance, int count, std::mt19937_64& rng);

// Site directions of texel centres.
std::vector<glm::dvec3> texel_centres(const ImportanceMap& importance, std::span<const std::size_t> texels);

// random: independent importance samples (Szirmay-Kalos et al. §1.2), texel centres.
SiteSet sites_random(const ImportanceMap& importance, int count, std::uint64_t seed);

// Floyd-Steinberg halftoning (Szirmay-Kalos et al. §1.3, Listing 1.1) of per-texel weights into `count` samples:
// serpentine scan, threshold S / (2M), a sample removes S / M, error weights 3/8 (next), 3/8 (below),
// 1/4 (below next; around the seam, a neighbour on the sphere). The error is diffused between blocks of
// B x B texels (B a power of two, as large as keeps at least kBlocksPerSample blocks per sample), not
// single texels: with M << texels a texel holds a tiny fraction of the threshold, and the error would
// spread over whole rows without firing until the last one (the warm-up Szirmay-Kalos et al. warn about for few
// samples). For the same reason a dark block passes more along its row, as Szirmay-Kalos et al. advise: the share
// going to the next block is max(3/8, min(15/16, 1 - g)), g the block's weight over 2 thresholds, the
// rest 3:2 below and below-next. Each sample stands at its block's weighted mean direction. Mass is
// conserved up to the error left at the last block, so there are M samples barring rounding, M - 1 at
// worst: where blocks saturate (M near their number) the missing ones go to the heaviest blocks not
// chosen. `start_error` (in thresholds, [-1, 1]) shifts the pattern.
inline constexpr int kBlocksPerSample = 64;
std::vector<glm::dvec3> floyd_steinberg_samples(const ImportanceMap& grid, std::span<const float> weight, int count,
                                                double start_error);

// fs: floyd_steinberg_samples of the importance map.
SiteSet sites_floyd_steinberg(const ImportanceMap& importance, int count);

// Cuts the map into `count` lat-long rectangles of equal importance (up to texel granularity) by
// recursive splits across the angularly longest side (width measured at the middle latitude), a region
// meant for n cells splitting into n/2 and n - n/2 in proportion; returns the regions' importance
// centroids. A region that cannot be split into its cells (too few texels, or one bright texel) gives
// its other sites at its heaviest texels, so there are always `count` sites (count <= texels).
std::vector<glm::dvec3> equal_importance_regions(const ImportanceMap& importance, int count);

// mediancut: Debevec 2005, solid-angle corrected: equal_importance_regions for the largest 2^k <= count
// (every split at the importance median).
SiteSet sites_median_cut(const ImportanceMap& importance, int count);

// lloyd: weighted Lloyd relaxation on the sphere (Barsi et al. §2.1): every site moves towards the
// normalised importance-weighted mean direction of its cell, decreasing E = sum I (1 - w . s), until an
// iteration gains less than kLloydEnergyTolerance of E. The steps are over-relaxed
// (`over_relaxation`, 1 for Lloyd's own steps); one that raises E is replaced by the plain step to the
// centroid. Starts from Floyd-Steinberg samples of sqrt(I dw) (Lloyd's
// asymptotic site density, stratified; the seed shifts the halftoning), which saves most of the
// hundreds of iterations independent importance samples need to even out. Coarse to fine: converges
// first at 1/factor of the resolution for each of kLloydCoarseFactors (an iteration there costs about
// 1/factor^2), then again at full resolution, where only a few iterations remain.
inline constexpr double kLloydOverRelaxation = 1.9;
SiteSet sites_lloyd(const ImportanceMap& importance, int count, std::uint64_t seed, const Partition& partition,
                    double over_relaxation = kLloydOverRelaxation);

// ccvt: capacity-constrained Voronoi tessellation as a power diagram (Balzer et al. 2009; de Goes et
// al. 2012). Starts at the centroids of equal_importance_regions (so it takes no seed); the biases solve
// the capacity problem (equal importance per cell) by damped Newton steps, first on blurred importance;
// then the sites move towards their cells' centroids, the biases following. A texel heavier than an
// equal share T / N (a sun) cannot be split: it is left out of the sharing, so the cell that holds it
// carries it and one share of the rest besides, and every other cell one share.
// The assignment is the power diagram's, then balance_texels on the shared importance: its cells are
// the power cells up to whole texels passed across their borders, so they are no longer exactly the
// nearest-site cells of the returned sites and biases (SiteSet::texel_cell holds them).
SiteSet sites_ccvt(const ImportanceMap& importance, int count, const Partition& partition);

// The importance CCVT shares out: `importance` with the texels heavier than an equal share (total /
// count) set to zero, where there are such texels and at most count / 4 of them (a sun's); otherwise
// `importance` itself. A sun's cell carries the sun and one share of the rest.
ImportanceMap shareable_importance(const ImportanceMap& importance, int count);

// CCVT's last step, whole-texel balancing (the swaps of Balzer et al. 2009, restricted to cell
// borders): passes over the border texels (a 4-neighbour, across the u = 0/1 seam too, in another
// cell; nothing beyond the poles) in scan order. A texel of importance w > 0 moves from its cell a to
// the lightest neighbouring cell b when I_a - I_b > w: that changes sum_k (I_k - share)^2 by
// 2 w^2 - 2 w (I_a - I_b) < 0, so every move lowers it and neighbouring cells end within a texel of each
// other. Cells closer than kCcvtBalanceTolerance of a share (total / cell_count) trade nothing: the
// borders of cells already in balance stay the power diagram's, not frayed by moves of dark texels that
// gain next to nothing. Texels of no importance (those shareable_importance leaves out) never move; a cell never gives
// up its last texel, nor a texel whose removal would cut it in two locally (not a simple point of its
// 8-neighbourhood). Stops after a pass that moves nothing or after `max_passes`; each pass visits only
// the border texels. Sequential and deterministic. Returns the passes run and texels moved.
struct TexelBalance {
    int passes = 0;
    std::size_t moves = 0;
};
inline constexpr int kCcvtBalancePasses = 64;
inline constexpr double kCcvtBalanceTolerance = 0.02;
TexelBalance balance_texels(const ImportanceMap& importance, std::span<std::uint16_t> texel_cell, int cell_count,
                            int max_passes = kCcvtBalancePasses);

// Cells left without a texel (sites closer than a texel, a power cell squeezed out, a median-cut region
// too small for its cells): each such cell's site moves onto the heaviest texel of the cell with the
// largest importance x solid angle (as the relaxations reseed empty cells; a donor with two texels at
// least, its heaviest texel other than the one its own site stands on), takes the donor's bias, and the
// texels are assigned again, until every cell holds a texel or `max_rounds` are run. A site on a texel
// centre wins that texel, so each round fills every empty cell it began with. `bias` is empty or one
// per site. Returns the rounds that moved a site (0 when no cell was empty).
int fill_empty_cells(const ImportanceMap& importance, const Partition& partition, std::vector<glm::dvec3>& sites,
                     std::vector<double>& bias, std::span<std::uint16_t> texel_cell, int max_rounds = 8);

inline constexpr double kLloydEnergyTolerance = 1e-4;
inline constexpr int kLloydMaxIterations = 500;    // per resolution
inline constexpr int kLloydCoarseFactors[] = {2};  // Lloyd converges at 1/2 of the resolution first
// CCVT: the capacity problem is solved first at coarse resolutions on blurred importance ({factor,
// blur radius in coarse texels}), then the sites move at the working resolution (1/kCcvtWorkingFactor),
// and a last balance runs at full resolution. Each stage has a budget of evaluations (an assignment and
// a pass over the texels). The moves stop when the sharing cells' importance varies by under
// kCcvtCapacityTolerance (coefficient of variation) and no site is further from its cell's centroid than
// kCcvtRelativeMovementTolerance of the cell's radius, or after kCcvtMaxIterations moves or
// kCcvtMaxEvaluations evaluations, keeping the best balanced state seen.
inline constexpr std::pair<int, int> kCcvtCoarseLevels[] = {{4, 4}, {2, 2}};
inline constexpr int kCcvtWorkingFactor = 2;           // unless a coarse texel holds more than
inline constexpr double kCcvtCoarseTexelShare = 0.05;  // this fraction of a share
inline constexpr int kCcvtEvaluationsPerLevel = 30;
inline constexpr int kCcvtNewtonStepsPerIteration = 2;
inline constexpr int kCcvtPolishEvaluations = 20;
inline constexpr double kCcvtCapacityTolerance = 0.02;
inline constexpr double kCcvtSmallestStep = 1.0 / 32.0;  // Newton step lengths tried: 1, 1/2, .., this
inline constexpr double kCcvtMoveFraction = 0.1;         // a site moves at most this fraction of its cell's radius
inline constexpr double kCcvtRelativeMovementTolerance = 0.1;
inline constexpr int kCcvtMaxIterations = 40;
inline constexpr int kCcvtMaxEvaluations = 300;
// A capacity solve stops when its last kCcvtStallSteps steps gained less than kCcvtStallGain of the
// variation between them: the steps after a stall buy little balance for most of the solve's time
// (docs/PERFORMANCE.md, "Decomposition").
inline constexpr int kCcvtStallSteps = 2;
inline constexpr double kCcvtStallGain = 0.05;

}  // namespace envshadow
