// Prefiltering the environment for the ratio estimator (docs/DESIGN.md §4.1) through spherical harmonics.
// With Y_lm = P_lm(cos theta) e^{i m phi} orthonormal, the map's coefficients are the exact texel sums
//   c_lm = sum over texels of L dw P_lm(cos theta) e^{-i m phi}
// (so the result is the direct numerical integral of the texels, the twin test's truth, up to the
// truncation of the lobe's expansion), and by Funk-Hecke any lobe K(r . w) gives
//   integral of L K(r . w) dw = sum_lm Lambda_l c_lm Y_lm(r),  Lambda_l = 2 pi integral K(t) P_l(t) dt.
// The Phong lobe's Lambda_l falls like exp(-l^2 / 2n), so level n needs l up to ~4.5 sqrt(n); its grid
// follows the lobe's width (texel spacing ~ a quarter of 1 / sqrt(n), where bilinear lookups err < 1%).
#include "env/prefilter.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <numbers>
#include <utility>

#include "env/latlong.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace envshadow {

namespace detail {

void* allocate_level_storage(std::size_t bytes) {
    constexpr std::size_t kHugePage = std::size_t(2) << 20;
    void* storage = nullptr;
    if (bytes >= kHugePage / 2) {
        const std::size_t rounded = (bytes + kHugePage - 1) & ~(kHugePage - 1);
        storage = std::aligned_alloc(kHugePage, rounded);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        if (storage) madvise(storage, rounded, MADV_HUGEPAGE);  // advice only
#endif
    } else {
        storage = std::malloc(std::max<std::size_t>(bytes, 1));
    }
    if (!storage) throw std::bad_alloc();
    return storage;
}

void free_level_storage(void* storage) noexcept {
    std::free(storage);
}

}  // namespace detail

namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;
// n_k = 10^(k / 8) up to 1000 (1, 10, 100, 1000 exact; neighbours 1.33x apart), then 10^(1/4) apart up to
// 10^4: the sharp lobes' grids and bands cost the most.
constexpr int kFineLevels = 25;
constexpr int kLevels = kFineLevels + 4;
double level_shininess(int k) {
    return k < kFineLevels ? std::pow(10.0, k / 8.0) : std::pow(10.0, 3.0 + (k - kFineLevels + 1) / 4.0);
}
// The level coordinate of shininess n: k + fraction, linear in log n within each spacing.
double level_coordinate(double n) {
    const double decades = std::log10(n);
    return decades <= 3.0 ? decades * 8.0 : kFineLevels - 1 + (decades - 3.0) * 4.0;
}
constexpr int kMaxGridWidth = 1024;      // levels and the source are at most 1024 x 512
constexpr int kMinGridWidth = 64;        // E (n = 1): 64 x 32
constexpr double kTexelsPerLobe = 32.0;  // grid width ~ 32 sqrt(n) (spacing ~ 0.2 / sqrt(n)): 24 left 4% at n = 100

// Rows are processed kBlock at a time, one lane each: arrays laid out [..][lane] make every inner loop kBlock
// independent lanes (one or two SIMD vectors) with no horizontal sums, and share the recurrences' latency.
constexpr int kBlock = 8;

// Scratch arrays, uninitialised, on the levels' storage (huge pages from 1 MB).
struct StorageDeleter {
    void operator()(void* storage) const noexcept { detail::free_level_storage(storage); }
};
template <class T>
using Scratch = std::unique_ptr<T[], StorageDeleter>;
template <class T>
Scratch<T> scratch(std::size_t count) {
    return Scratch<T>(static_cast<T*>(detail::allocate_level_storage(count * sizeof(T))));
}

// The hot loops below are compiled twice, for the baseline x86-64 and for x86-64-v3 (AVX2 and FMA: 4 doubles a
// vector instead of 2, a * b + c in one rounding; this file is compiled with -ffp-contract=fast), and the
// processor picks one at load time; elsewhere once.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define ENVSHADOW_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define ENVSHADOW_VECTOR_CLONES
#endif

// Four doubles with element-wise arithmetic (GCC and Clang vector extensions): one AVX2 register in the
// x86-64-v3 clones, two SSE2 ones in the baseline. A block's kBlock lanes are two of them; the kernels below
// hold their accumulators and butterflies in such vectors so that they stay in the 16 registers.
constexpr int kVector = 4;
typedef double Vector __attribute__((vector_size(kVector * sizeof(double))));
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"  // Vector by value only between this file's always-inlined helpers
#endif
[[gnu::always_inline]] inline Vector load(const double* from) {
    Vector v;
    std::memcpy(&v, from, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void store(double* to, const Vector& v) {
    std::memcpy(to, &v, sizeof v);
}
[[gnu::always_inline]] inline double lane_sum(const Vector& v) {
    return (v[0] + v[1]) + (v[2] + v[3]);
}

// Radix-2 FFT tables for size n: the bit reversal and the twiddles e^{i pi k / h} of each stage.
struct FftTables {
    int n = 0;
    std::vector<int> reversed;     // the input of index i goes to reversed[i]
    std::vector<double> cos, sin;  // the stage of half-length h: entries h - 1 .. 2h - 2
    explicit FftTables(int size)
        : n(size), reversed(std::size_t(size)), cos(std::size_t(std::max(size - 1, 1))), sin(cos.size()) {
        for (int i = 0, j = 0; i < n; ++i) {
            reversed[std::size_t(i)] = j;
            int bit = n >> 1;
            for (; j & bit; bit >>= 1) j ^= bit;
            j ^= bit;
        }
        for (int half = 1; half < n; half <<= 1)
            for (int k = 0; k < half; ++k) {
                cos[std::size_t(half - 1 + k)] = std::cos(kPi * k / half);
                sin[std::size_t(half - 1 + k)] = std::sin(kPi * k / half);
            }
    }
};

// (a, b) -> (a + b, (a - b) w) in every lane: the decimation-in-frequency butterfly.
[[gnu::always_inline]] inline void butterfly(Vector& ar, Vector& ai, Vector& br, Vector& bi, double wr, double wi) {
    const Vector dr = ar - br, di = ai - bi;
    ar += br, ai += bi;
    br = dr * wr - di * wi, bi = dr * wi + di * wr;
}

// a_j -> sum_k a_k e^{sign 2 pi i j k / N} for kBlock rows at once, in place on split real and imaginary parts
// laid out [index][lane]: the input in natural order, the output in bit-reversed order (index j at
// FftTables::reversed[j]; the callers read it so). Decimation in frequency, two stages at a time (radix 2^2:
// four points loaded once for two stages' butterflies, so a block's 128 KB of rows at N = 1024 is swept five
// times instead of ten), the last two (twiddles 1 and +-i) without multiplications.
ENVSHADOW_VECTOR_CLONES
void block_fft(const FftTables& fft, double* re, double* im, double sign) {
    const int n = fft.n;
    int half = n / 2;
    for (; half >= 4; half /= 4) {  // stages h and h / 2
        const int quarter = half / 2;
        const std::size_t stride = std::size_t(quarter) * kBlock;
        for (int start = 0; start < n; start += 2 * half)
            for (int k = 0; k < quarter; ++k) {
                // Stage h: (0, 2) with the twiddle e^{sign i pi k / h}, (1, 3) with e^{sign i pi (k + h/2) / h};
                // stage h / 2: (0, 1) and (2, 3) with e^{sign i pi k / (h/2)}.
                const std::size_t w0 = std::size_t(half - 1 + k), w1 = w0 + std::size_t(quarter);
                const std::size_t w2 = std::size_t(quarter - 1 + k);
                for (int lane = 0; lane < kBlock; lane += kVector) {
                    double* r = re + std::size_t(start + k) * kBlock + std::size_t(lane);
                    double* i = im + std::size_t(start + k) * kBlock + std::size_t(lane);
                    Vector x0r = load(r), x1r = load(r + stride), x2r = load(r + 2 * stride),
                           x3r = load(r + 3 * stride);
                    Vector x0i = load(i), x1i = load(i + stride), x2i = load(i + 2 * stride),
                           x3i = load(i + 3 * stride);
                    butterfly(x0r, x0i, x2r, x2i, fft.cos[w0], sign * fft.sin[w0]);
                    butterfly(x1r, x1i, x3r, x3i, fft.cos[w1], sign * fft.sin[w1]);
                    butterfly(x0r, x0i, x1r, x1i, fft.cos[w2], sign * fft.sin[w2]);
                    butterfly(x2r, x2i, x3r, x3i, fft.cos[w2], sign * fft.sin[w2]);
                    store(r, x0r), store(r + stride, x1r), store(r + 2 * stride, x2r), store(r + 3 * stride, x3r);
                    store(i, x0i), store(i + stride, x1i), store(i + 2 * stride, x2i), store(i + 3 * stride, x3i);
                }
            }
    }
    if (half == 2) {  // stages 2 and 1: (0, 2) and (1, 3) with twiddles 1 and e^{sign i pi / 2}, then (0, 1), (2, 3)
        for (int start = 0; start < n; start += 4)
            for (int lane = 0; lane < kBlock; lane += kVector) {
                double* r = re + std::size_t(start) * kBlock + std::size_t(lane);
                double* i = im + std::size_t(start) * kBlock + std::size_t(lane);
                Vector x0r = load(r), x1r = load(r + kBlock), x2r = load(r + 2 * kBlock), x3r = load(r + 3 * kBlock);
                Vector x0i = load(i), x1i = load(i + kBlock), x2i = load(i + 2 * kBlock), x3i = load(i + 3 * kBlock);
                const Vector a0r = x0r + x2r, a0i = x0i + x2i, a2r = x0r - x2r, a2i = x0i - x2i;
                const Vector a1r = x1r + x3r, a1i = x1i + x3i;
                const Vector a3r = sign * (x3i - x1i), a3i = sign * (x1r - x3r);  // (x1 - x3) e^{sign i pi / 2}
                store(r, a0r + a1r), store(r + kBlock, a0r - a1r), store(r + 2 * kBlock, a2r + a3r);
                store(r + 3 * kBlock, a2r - a3r);
                store(i, a0i + a1i), store(i + kBlock, a0i - a1i), store(i + 2 * kBlock, a2i + a3i);
                store(i + 3 * kBlock, a2i - a3i);
            }
    } else if (half == 1) {  // the last stage alone: (0, 1) with twiddle 1
        for (int start = 0; start < n; start += 2)
            for (int lane = 0; lane < kBlock; lane += kVector) {
                double* r = re + std::size_t(start) * kBlock + std::size_t(lane);
                double* i = im + std::size_t(start) * kBlock + std::size_t(lane);
                Vector x0r = load(r), x1r = load(r + kBlock), x0i = load(i), x1i = load(i + kBlock);
                store(r, x0r + x1r), store(r + kBlock, x0r - x1r), store(i, x0i + x1i), store(i + kBlock, x0i - x1i);
            }
    }
}

int next_power_of_two(int x) {
    return int(std::bit_ceil(unsigned(std::max(x, 1))));
}

// Orthonormal associated Legendre functions (no Condon-Shortley phase) by the standard stable recurrences:
//   P_mm = sqrt((2m+1)/(2m)) s P_{m-1,m-1},  P_{m+1,m} = sqrt(2m+3) x P_mm,
//   P_lm = a_lm (x P_{l-1,m} - b_lm P_{l-2,m}) = (a_lm x) P_{l-1,m} - (a_lm b_lm) P_{l-2,m},
// the last with one fused multiply-add on the recurrence's dependency chain. Tabled by order, then degree:
// entry offset(m) + l - m.
struct LegendreRecurrence {
    int lmax;
    std::vector<double> sectoral_factor;  // sqrt((2m+1)/(2m)), m >= 1
    std::vector<double> a, ab;            // a_lm, a_lm b_lm for l >= m + 2
    std::size_t offset(int m) const {
        return std::size_t(m) * std::size_t(lmax + 1) - std::size_t(m) * std::size_t(m - 1) / 2;
    }
    explicit LegendreRecurrence(int max_degree)
        : lmax(max_degree), sectoral_factor(std::size_t(max_degree) + 1), a(offset(max_degree + 1)), ab(a.size()) {
        for (int m = 1; m <= lmax; ++m) sectoral_factor[std::size_t(m)] = std::sqrt((2.0 * m + 1.0) / (2.0 * m));
        tbb::parallel_for(0, lmax + 1, [&](int m) {
            for (int l = m + 2; l <= lmax; ++l) {
                const double l2 = double(l) * l, m2 = double(m) * m, lm1 = double(l - 1) * (l - 1);
                const double a_lm = std::sqrt((4.0 * l2 - 1.0) / (l2 - m2));
                a[offset(m) + std::size_t(l - m)] = a_lm;
                ab[offset(m) + std::size_t(l - m)] = a_lm * std::sqrt((lm1 - m2) / (4.0 * lm1 - 1.0));
            }
        });
    }
};

// P_mm(s) of kBlock rows for m = 0..last, at pmm[m * kBlock + b].
void sectoral(const LegendreRecurrence& recurrence, const double* s, int last, double* pmm) {
    for (int b = 0; b < kBlock; ++b) pmm[b] = std::sqrt(1.0 / (4.0 * kPi));
    for (int m = 1; m <= last; ++m)
        for (int b = 0; b < kBlock; ++b)
            pmm[std::size_t(m) * kBlock + std::size_t(b)] =
                recurrence.sectoral_factor[std::size_t(m)] * s[b] * pmm[std::size_t(m - 1) * kBlock + std::size_t(b)];
}

// The highest order whose sectoral value has not underflowed to zero in some lane: above it, every P_lm of the
// block is zero (the recurrences start from P_mm), near the poles where sin theta is small.
int last_nonzero_order(const double* pmm, int last) {
    while (last > 0 && std::all_of(pmm + std::size_t(last) * kBlock, pmm + std::size_t(last + 1) * kBlock,
                                   [](double p) { return p == 0.0; }))
        --last;
    return last;
}

// c_lm = sum over row pairs of P_lm(x) (E_m if l - m is even, O_m if odd: the pair's even and odd spectra) for
// one order m, l = m..lmax, into c[(l - m) * 6 + q]. Degree by degree, every block's recurrence advanced one step
// (state in p1, p2): the blocks are independent chains, and the sums stay in registers per lane, reduced across
// lanes once per degree; four lanes at a time. The blocks nearest the pole whose sectoral values underflowed to
// zero add nothing and are skipped.
ENVSHADOW_VECTOR_CLONES
void order_coefficients(const LegendreRecurrence& recurrence, int m, int blocks, int bands, int parities,
                        const double* spectra, const double* block_x, const double* block_pmm, double* p1, double* p2,
                        double* c) {
    auto pmm_of = [&](int block) {
        return &block_pmm[(std::size_t(block) * std::size_t(bands) + std::size_t(m)) * kBlock];
    };
    auto spectrum = [&](int block, std::size_t parity) {  // spectra[block][m][parity][q][lane]
        return &spectra[((std::size_t(block) * std::size_t(bands) + std::size_t(m)) * std::size_t(parities) + parity) *
                        6 * kBlock];
    };
    int first_block = 0;
    while (first_block < blocks &&
           std::all_of(pmm_of(first_block), pmm_of(first_block) + kBlock, [](double p) { return p == 0.0; }))
        ++first_block;
    const double start = std::sqrt(2.0 * m + 3.0);
    const std::size_t table = recurrence.offset(m);
    for (int l = m; l <= recurrence.lmax; ++l)
        for (int q = 0; q < 6; ++q) c[std::size_t(l - m) * 6 + std::size_t(q)] = 0.0;
    for (int lane = 0; lane < kBlock; lane += kVector)
        for (int l = m; l <= recurrence.lmax; ++l) {
            const double a = l >= m + 2 ? recurrence.a[table + std::size_t(l - m)] : 0.0;
            const double ab = l >= m + 2 ? recurrence.ab[table + std::size_t(l - m)] : 0.0;
            const std::size_t parity = std::size_t((l - m) & (parities - 1));  // 0 when one parity
            Vector sum0 = {}, sum1 = {}, sum2 = {}, sum3 = {}, sum4 = {}, sum5 = {};
            for (int block = first_block; block < blocks; ++block) {
                const std::size_t at = std::size_t(block) * kBlock + std::size_t(lane);
                const Vector x = load(&block_x[at]), q1 = load(&p1[at]), q2 = load(&p2[at]);
                const Vector p = l == m       ? load(pmm_of(block) + lane)
                                 : l == m + 1 ? start * x * q1
                                              : (a * x) * q1 - ab * q2;
                store(&p2[at], q1), store(&p1[at], p);
                const double* f = spectrum(block, parity) + lane;
                sum0 += p * load(f), sum1 += p * load(f + kBlock), sum2 += p * load(f + 2 * kBlock);
                sum3 += p * load(f + 3 * kBlock), sum4 += p * load(f + 4 * kBlock), sum5 += p * load(f + 5 * kBlock);
            }
            double* out = &c[std::size_t(l - m) * 6];
            out[0] += lane_sum(sum0), out[1] += lane_sum(sum1), out[2] += lane_sum(sum2);
            out[3] += lane_sum(sum3), out[4] += lane_sum(sum4), out[5] += lane_sum(sum5);
        }
}

// P_lm(x_b) of one block of rows for l = m..last, at legendre[(l - m) * kBlock + b]: the block's two vectors are
// two independent dependency chains.
ENVSHADOW_VECTOR_CLONES
void order_legendre(const LegendreRecurrence& recurrence, const double* x, const double* pmm, int m, int last,
                    double* legendre) {
    const Vector x_lo = load(x), x_hi = load(x + kVector);
    Vector p1_lo = load(pmm), p1_hi = load(pmm + kVector);
    store(legendre, p1_lo), store(legendre + kVector, p1_hi);
    if (m + 1 > last) return;
    const double start = std::sqrt(2.0 * m + 3.0);
    Vector p2_lo = p1_lo, p2_hi = p1_hi;
    p1_lo = start * x_lo * p2_lo, p1_hi = start * x_hi * p2_hi;
    store(legendre + kBlock, p1_lo), store(legendre + kBlock + kVector, p1_hi);
    const double* a = &recurrence.a[recurrence.offset(m)];
    const double* ab = &recurrence.ab[recurrence.offset(m)];
    for (int k = 2; k <= last - m; ++k) {
        const Vector p_lo = (a[k] * x_lo) * p1_lo - ab[k] * p2_lo, p_hi = (a[k] * x_hi) * p1_hi - ab[k] * p2_hi;
        store(legendre + std::size_t(k) * kBlock, p_lo), store(legendre + std::size_t(k) * kBlock + kVector, p_hi);
        p2_lo = p1_lo, p2_hi = p1_hi, p1_lo = p_lo, p1_hi = p_hi;
    }
}

// For one order m and one block of rows: sums[parity of l - m][re/im x rgb][lane] = sum over l = m..band of that
// parity of factors[l - m] c[(l - m) * 6 + q] P_lm(x_lane) (the level's Funk-Hecke factors times the order's
// coefficients). Four lanes at a time, so that the twelve accumulators (six sums, two parities), the two
// Legendre vectors and a broadcast fit the 16 vector registers.
ENVSHADOW_VECTOR_CLONES
void degree_sums(const double* legendre, const double* c, const double* factors, int m, int band,
                 double (&sums)[2][6][kBlock]) {
    const int count = band - m + 1;
    for (int lane = 0; lane < kBlock; lane += kVector) {
        Vector e0 = {}, e1 = {}, e2 = {}, e3 = {}, e4 = {}, e5 = {};
        Vector o0 = {}, o1 = {}, o2 = {}, o3 = {}, o4 = {}, o5 = {};
        int k = 0;
        for (; k + 1 < count; k += 2) {
            const Vector pe = load(&legendre[std::size_t(k) * kBlock + std::size_t(lane)]) * factors[k];
            const Vector po = load(&legendre[std::size_t(k + 1) * kBlock + std::size_t(lane)]) * factors[k + 1];
            const double* ce = &c[std::size_t(k) * 6];
            e0 += pe * ce[0], e1 += pe * ce[1], e2 += pe * ce[2], e3 += pe * ce[3], e4 += pe * ce[4], e5 += pe * ce[5];
            o0 += po * ce[6], o1 += po * ce[7], o2 += po * ce[8], o3 += po * ce[9], o4 += po * ce[10],
                o5 += po * ce[11];
        }
        if (k < count) {
            const Vector pe = load(&legendre[std::size_t(k) * kBlock + std::size_t(lane)]) * factors[k];
            const double* ce = &c[std::size_t(k) * 6];
            e0 += pe * ce[0], e1 += pe * ce[1], e2 += pe * ce[2], e3 += pe * ce[3], e4 += pe * ce[4], e5 += pe * ce[5];
        }
        store(&sums[0][0][lane], e0), store(&sums[0][1][lane], e1), store(&sums[0][2][lane], e2);
        store(&sums[0][3][lane], e3), store(&sums[0][4][lane], e4), store(&sums[0][5][lane], e5);
        store(&sums[1][0][lane], o0), store(&sums[1][1][lane], o1), store(&sums[1][2][lane], o2);
        store(&sums[1][3][lane], o3), store(&sums[1][4][lane], o4), store(&sums[1][5][lane], o5);
    }
}

// The map at kMaxGridWidth x kMaxGridWidth / 2: wider maps box-halved (weighted by texel solid angle),
// narrower ones (builtin:constant, small skies) repeated texel by texel, so that the sharpest lobe's band
// fits the source's (a band cut short would overshoot).
EnvironmentMap resampled(const EnvironmentMap& map) {
    if (map.width < kMaxGridWidth) {
        EnvironmentMap larger;
        larger.width = kMaxGridWidth;
        larger.height = kMaxGridWidth / 2;
        larger.texels.resize(std::size_t(larger.width) * std::size_t(larger.height));
        tbb::parallel_for(0, larger.height, [&](int j) {
            const int source_row = std::min(int(std::int64_t(j) * map.height / larger.height), map.height - 1);
            for (int i = 0; i < larger.width; ++i)
                larger.at(i, j) =
                    map.at(std::min(int(std::int64_t(i) * map.width / larger.width), map.width - 1), source_row);
        });
        return larger;
    }
    EnvironmentMap current = map;
    while (current.width > kMaxGridWidth && current.width % 2 == 0 && current.height % 2 == 0) {
        EnvironmentMap half;
        half.width = current.width / 2;
        half.height = current.height / 2;
        half.texels.resize(std::size_t(half.width) * std::size_t(half.height));
        tbb::parallel_for(0, half.height, [&](int j) {
            const double w0 = latlong::texel_solid_angle(2 * j, current.width, current.height);
            const double w1 = latlong::texel_solid_angle(2 * j + 1, current.width, current.height);
            for (int i = 0; i < half.width; ++i) {
                const glm::dvec3 top = glm::dvec3(current.at(2 * i, 2 * j)) + glm::dvec3(current.at(2 * i + 1, 2 * j));
                const glm::dvec3 bottom =
                    glm::dvec3(current.at(2 * i, 2 * j + 1)) + glm::dvec3(current.at(2 * i + 1, 2 * j + 1));
                half.at(i, j) = glm::vec3((top * w0 + bottom * w1) / (2.0 * (w0 + w1)));
            }
        });
        current = std::move(half);
    }
    return current;
}

}  // namespace

double phong_lobe_factor(int l, double n) {
    // Gradshteyn & Ryzhik 7.126.2: integral_0^1 t^n P_l(t) dt =
    //   sqrt(pi) 2^{-n-1} Gamma(n+1) / (Gamma(1 + n/2 - l/2) Gamma(n/2 + l/2 + 3/2)); 1/Gamma is 0 at the poles.
    const double x = 1.0 + 0.5 * n - 0.5 * l;
    double sign = 1.0;
    if (x <= 0.0) {
        if (x == std::floor(x)) return 0.0;
        sign = (int(std::ceil(-x)) % 2 == 1) ? -1.0 : 1.0;  // Gamma's sign on (-k, -k + 1)
    }
    const double log_value = 0.5 * std::log(kPi) - (n + 1.0) * std::log(2.0) + std::lgamma(n + 1.0) - std::lgamma(x) -
                             std::lgamma(0.5 * n + 0.5 * l + 1.5);
    return 2.0 * kPi * sign * std::exp(log_value);
}

LevelPair PrefilteredEnvironment::level_pair(float shininess) const {
    const int last = int(levels.size()) - 1;
    if (last <= 0) return {};
    const double n = std::clamp(double(shininess), double(kPrefilterMinShininess), double(kPrefilterMaxShininess));
    const double t = std::clamp(level_coordinate(n), 0.0, double(last));
    const int lower = std::min(int(std::floor(t + 1e-9)), last - 1);  // n = 1000 lands on its level, not below
    return {lower, lower + 1, float(std::clamp(t - lower, 0.0, 1.0))};
}

glm::vec3 PrefilteredEnvironment::sample(int level, const glm::dvec3& direction) const {
    const PrefilteredLevel& g = levels[std::size_t(level)];
    const glm::dvec2 uv = latlong::uv(direction);
    const double x = uv.x * g.width - 0.5, y = uv.y * (g.height - 1);
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    const int i0 = (int(fx) % g.width + g.width) % g.width, i1 = (i0 + 1) % g.width;
    const int j0 = int(fy), j1 = std::min(j0 + 1, g.height - 1);
    auto at = [&](int i, int j) {
        return glm::dvec3(g.texels[std::size_t(j) * std::size_t(g.width) + std::size_t(i)]);
    };
    const glm::dvec3 top = at(i0, j0) * (1.0 - ax) + at(i1, j0) * ax;
    const glm::dvec3 bottom = at(i0, j1) * (1.0 - ax) + at(i1, j1) * ax;
    return glm::vec3(top * (1.0 - ay) + bottom * ay);
}

glm::vec3 PrefilteredEnvironment::irradiance(const glm::dvec3& n) const {
    return float(kPi) * sample(0, n);  // S_1 = E; level 0 stores S_1 (1 + 1) / (2 pi)
}

glm::vec3 PrefilteredEnvironment::specular(const glm::dvec3& r, float shininess) const {
    const LevelPair pair = level_pair(shininess);
    const glm::vec3 mean = sample(pair.lower, r) * (1.0f - pair.weight) + sample(pair.upper, r) * pair.weight;
    return mean * float(2.0 * kPi / (double(shininess) + 1.0));
}

PrefilteredEnvironment prefilter_environment(const EnvironmentMap& full_map, Hemisphere hemisphere) {
    const auto start = std::chrono::steady_clock::now();
    // A 1024-wide map is used as it is (no copy: 6 MB of page faults).
    const EnvironmentMap resampled_map = full_map.width == kMaxGridWidth ? EnvironmentMap{} : resampled(full_map);
    const EnvironmentMap& map = full_map.width == kMaxGridWidth ? full_map : resampled_map;
    const int w = map.width, h = map.height;
    const int source_band = std::max(w / 2 - 1, 1);

    PrefilteredEnvironment result;
    struct LevelPlan {
        int band;
        std::vector<double> factors;  // Lambda_l (n + 1) / (2 pi), l = 0..band
    };
    std::vector<LevelPlan> plans;
    int lmax = 0;
    for (int k = 0; k < kLevels; ++k) {
        PrefilteredLevel& level = result.levels.emplace_back();
        const double n = level_shininess(k);
        level.shininess = float(n);
        level.width =
            std::clamp(next_power_of_two(int(std::ceil(kTexelsPerLobe * std::sqrt(n)))), kMinGridWidth, kMaxGridWidth);
        level.height = level.width / 2;
        LevelPlan& plan = plans.emplace_back();
        plan.band = std::min({int(std::ceil(4.5 * std::sqrt(n) + 24.0)), level.width / 2 - 1, source_band});
        for (int l = 0; l <= plan.band; ++l) plan.factors.push_back(phong_lobe_factor(l, n) * (n + 1.0) / (2.0 * kPi));
        lmax = std::max(lmax, plan.band);
    }
    const LegendreRecurrence recurrence(lmax);
    const int bands = lmax + 1;

    // The levels of one grid size share the rows' Legendre recurrences (up to the group's largest band), so
    // they are synthesised together.
    struct Group {
        std::size_t first, end;
        int width, height, band, north, blocks;
        FftTables fft;
        std::vector<double> shift_re, shift_im;  // e^{i pi m / W}: the columns' half texel
    };
    std::vector<Group> groups;
    std::size_t row_doubles = std::size_t(3 * 2) * std::size_t(w) * kBlock;  // the analysis' three transforms
    for (std::size_t first = 0; first < result.levels.size();) {
        std::size_t end = first + 1;
        while (end < result.levels.size() && result.levels[end].width == result.levels[first].width) ++end;
        const int width = result.levels[first].width, height = result.levels[first].height;
        int band = 0;
        for (std::size_t k = first; k < end; ++k) band = std::max(band, plans[k].band);
        // Rows j and H - 1 - j mirror each other: the northern half's recurrences give both.
        const int north = (height + 1) / 2;
        Group& group = groups.emplace_back(
            Group{first, end, width, height, band, north, (north + kBlock - 1) / kBlock, FftTables(width), {}, {}});
        for (int m = 0; m <= band; ++m) {
            const Complex shift = std::polar(1.0, kPi * m / width);
            group.shift_re.push_back(shift.real());
            group.shift_im.push_back(shift.imag());
        }
        row_doubles = std::max(row_doubles, (end - first) * 3 * 2 * std::size_t(width) * kBlock);
        first = end;
    }

    // Row pairs: the northern row r and its mirror h - 1 - r. P_lm(-x) = (-1)^{l+m} P_lm(x), so a pair enters the
    // coefficients through the sum of its rows' spectra (even l - m) and their difference (odd l - m), and the
    // recurrences run over the northern rows only.
    const int pairs = (h + 1) / 2;
    const int blocks = (pairs + kBlock - 1) / kBlock;

    // Per-thread scratch, reused by every stage: complex rows laid out [..][index][lane] and the recurrences.
    struct ThreadScratch {
        Scratch<double> rows, pmm, legendre, p1, p2;
    };
    tbb::enumerable_thread_specific<ThreadScratch> thread_scratch;
    auto local_scratch = [&]() -> ThreadScratch& {
        ThreadScratch& local = thread_scratch.local();
        if (!local.rows) {
            local.rows = scratch<double>(row_doubles);
            local.pmm = scratch<double>(std::size_t(bands) * kBlock);
            local.legendre = scratch<double>(std::size_t(bands) * kBlock);
            local.p1 = scratch<double>(std::size_t(blocks) * kBlock);
            local.p2 = scratch<double>(std::size_t(blocks) * kBlock);
        }
        return local;
    };

    // Row spectra of L dw: F_j(m) = dw_j sum_i L_ij e^{-i m phi_i}, phi_i = 2 pi (i + 0.5) / W, of each pair's
    // rows, as the even and odd spectra F_north +- F_south; 6 doubles (re, im of r, g, b) per pair, order and
    // parity: spectra[block][m][parity][q][lane]; one parity when no southern row is visible (the upper
    // hemisphere: both are F_north). Padding lanes are zero. With the P_mm of the northern rows:
    // block_pmm[block][m][lane].
    bool southern_rows = false;
    for (int r = 0; r < pairs; ++r)
        southern_rows =
            southern_rows || (h - 1 - r != r && hemisphere_texel_solid_angle(h - 1 - r, w, h, hemisphere) > 0.0);
    const int parities = southern_rows ? 2 : 1;
    Scratch<double> spectra =
        scratch<double>(std::size_t(blocks) * std::size_t(bands) * std::size_t(parities) * 6 * kBlock);
    Scratch<double> block_x = scratch<double>(std::size_t(blocks) * kBlock);
    Scratch<double> block_pmm = scratch<double>(std::size_t(blocks) * std::size_t(bands) * kBlock);
    std::vector<double> source_shift_re(static_cast<std::size_t>(bands)), source_shift_im(source_shift_re.size());
    for (int m = 0; m < bands; ++m) {  // e^{-i pi m / W}: phi_i's half texel
        const Complex shift = std::polar(1.0, -kPi * m / w);
        source_shift_re[std::size_t(m)] = shift.real(), source_shift_im[std::size_t(m)] = shift.imag();
    }
    const bool power_of_two = std::has_single_bit(unsigned(w));
    const FftTables source_fft(power_of_two ? w : 1);
    tbb::parallel_for(0, blocks, [&](int block) {
        ThreadScratch& local = local_scratch();
        alignas(64) double north_weight[kBlock], south_weight[kBlock], s[kBlock];
        int north_row[kBlock], south_row[kBlock];
        for (int b = 0; b < kBlock; ++b) {
            const int r = block * kBlock + b;
            double x = 0.0;
            north_weight[b] = south_weight[b] = s[b] = 0.0;
            north_row[b] = south_row[b] = 0;
            if (r < pairs) {
                north_row[b] = r, south_row[b] = h - 1 - r;
                north_weight[b] = hemisphere_texel_solid_angle(r, w, h, hemisphere);
                if (south_row[b] != r) south_weight[b] = hemisphere_texel_solid_angle(h - 1 - r, w, h, hemisphere);
                x = std::cos(kPi * (r + 0.5) / h);
                s[b] = std::sin(kPi * (r + 0.5) / h);
            }
            block_x[std::size_t(block) * kBlock + std::size_t(b)] = x;
        }
        sectoral(recurrence, s, lmax, &block_pmm[std::size_t(block) * std::size_t(bands) * kBlock]);

        // Three complex transforms of two real rows each: north red + i green, south red + i green, north blue +
        // i south blue. Z = X + i Y with X, Y real rows' spectra (X_{-m} = conj X_m) gives X_m = (Z_m + conj
        // Z_{-m}) / 2, Y_m = (Z_m - conj Z_{-m}) / 2i.
        const std::size_t row_size = std::size_t(w) * kBlock;
        double* z = local.rows.get();
        auto re_of = [&](int t) { return z + std::size_t(2 * t) * row_size; };
        auto im_of = [&](int t) { return z + std::size_t(2 * t + 1) * row_size; };
        if (power_of_two) {
            for (int i = 0; i < w; ++i)
                for (int b = 0; b < kBlock; ++b) {
                    // Rows outside the hemisphere (weight 0) read as zero, whatever they hold.
                    const glm::vec3 north = north_weight[b] > 0.0 ? map.at(i, north_row[b]) : glm::vec3(0.0f);
                    const glm::vec3 south = south_weight[b] > 0.0 ? map.at(i, south_row[b]) : glm::vec3(0.0f);
                    const std::size_t at = std::size_t(i) * kBlock + std::size_t(b);
                    re_of(0)[at] = north.r, im_of(0)[at] = north.g;
                    re_of(1)[at] = south.r, im_of(1)[at] = south.g;
                    re_of(2)[at] = north.b, im_of(2)[at] = south.b;
                }
            for (int t = 0; t < 3; ++t)
                if (t != 1 || southern_rows) block_fft(source_fft, re_of(t), im_of(t), -1.0);  // zeros stay zeros
        } else {  // a direct transform of the orders needed, m < bands (and their mirrors -m)
            std::vector<double> cos_table(static_cast<std::size_t>(w)), sin_table(cos_table.size());
            for (int i = 0; i < w; ++i)
                cos_table[std::size_t(i)] = std::cos(2.0 * kPi * i / w),
                sin_table[std::size_t(i)] = std::sin(2.0 * kPi * i / w);
            for (int m = 0; m < bands; ++m)
                for (int b = 0; b < kBlock; ++b) {
                    double sums[3][2][2] = {};  // [transform][re/im of sum L e^{-i m phi}][real row X or Y]
                    for (int i = 0; i < w; ++i) {
                        const std::size_t turn = std::size_t(std::int64_t(m) * i % w);
                        const double c = cos_table[turn], si = -sin_table[turn];
                        const glm::vec3 north = north_weight[b] > 0.0 ? map.at(i, north_row[b]) : glm::vec3(0.0f);
                        const glm::vec3 south = south_weight[b] > 0.0 ? map.at(i, south_row[b]) : glm::vec3(0.0f);
                        const double xs[3] = {north.r, south.r, north.b}, ys[3] = {north.g, south.g, south.b};
                        for (int t = 0; t < 3; ++t) {
                            sums[t][0][0] += xs[t] * c, sums[t][1][0] += xs[t] * si;
                            sums[t][0][1] += ys[t] * c, sums[t][1][1] += ys[t] * si;
                        }
                    }
                    // Stored as the transform of X + i Y would be, at m and -m.
                    const std::size_t p = std::size_t(m) * kBlock + std::size_t(b);
                    const std::size_t q = std::size_t((w - m) % w) * kBlock + std::size_t(b);
                    for (int t = 0; t < 3; ++t) {
                        re_of(t)[p] = sums[t][0][0] - sums[t][1][1], im_of(t)[p] = sums[t][1][0] + sums[t][0][1];
                        re_of(t)[q] = sums[t][0][0] + sums[t][1][1], im_of(t)[q] = sums[t][0][1] - sums[t][1][0];
                    }
                }
        }
        auto slot = [&](int m) {  // of Z_m: the FFT's output is bit-reversed, the direct transform's natural
            return std::size_t(power_of_two ? source_fft.reversed[std::size_t(m)] : m) * kBlock;
        };
        for (int m = 0; m < bands; ++m) {
            const std::size_t p = slot(m), q = slot((w - m) % w);
            const double shift_re = source_shift_re[std::size_t(m)], shift_im = source_shift_im[std::size_t(m)];
            double* even =
                &spectra[((std::size_t(block) * std::size_t(bands) + std::size_t(m)) * std::size_t(parities)) * 6 *
                         kBlock];
            double* odd = even + std::size_t(parities - 1) * 6 * kBlock;  // the same when one parity
            for (int c = 0; c < 3; ++c) {
                // The transform and the half of it that holds channel c of the north (X) and south (Y) rows.
                const int north_t = c < 2 ? 0 : 2, south_t = c < 2 ? 1 : 2;
                const bool north_imag = c == 1, south_imag = c != 0;
                for (int b = 0; b < kBlock; ++b) {
                    auto unpack = [&](int t, bool imag, double& value_re, double& value_im) {
                        const double zpr = re_of(t)[p + std::size_t(b)], zpi = im_of(t)[p + std::size_t(b)];
                        const double zqr = re_of(t)[q + std::size_t(b)], zqi = im_of(t)[q + std::size_t(b)];
                        value_re = imag ? 0.5 * (zpi + zqi) : 0.5 * (zpr + zqr);
                        value_im = imag ? 0.5 * (zqr - zpr) : 0.5 * (zpi - zqi);
                    };
                    double nr, ni, sr, si;
                    unpack(north_t, north_imag, nr, ni);
                    unpack(south_t, south_imag, sr, si);
                    nr *= north_weight[b], ni *= north_weight[b], sr *= south_weight[b], si *= south_weight[b];
                    const double er = nr + sr, ei = ni + si, or_ = nr - sr, oi = ni - si;
                    even[(2 * c) * kBlock + b] = er * shift_re - ei * shift_im;
                    even[(2 * c + 1) * kBlock + b] = er * shift_im + ei * shift_re;
                    odd[(2 * c) * kBlock + b] = or_ * shift_re - oi * shift_im;
                    odd[(2 * c + 1) * kBlock + b] = or_ * shift_im + oi * shift_re;
                }
            }
        }
    });

    // c_lm = sum over pairs of P_lm(cos theta) (F_north +- F_south)(m), one task per order m; 6 doubles per
    // coefficient, by order: coefficients[recurrence.offset(m) * 6 + (l - m) * 6 + q].
    Scratch<double> coefficients = scratch<double>(recurrence.offset(bands) * 6);
    tbb::parallel_for(0, bands, [&](int m) {
        ThreadScratch& local = local_scratch();
        order_coefficients(recurrence, m, blocks, bands, parities, spectra.get(), block_x.get(), block_pmm.get(),
                           local.p1.get(), local.p2.get(), &coefficients[recurrence.offset(m) * 6]);
    });

    // Each level: G_m(theta) = sum_l Lambda_l c_lm P_lm(cos theta), then each row by an inverse FFT of
    // G_0 + 2 sum_{m > 0} G_m e^{i m phi}. One task per group and block of kBlock northern rows, whose
    // recurrences give its southern mirrors too, from the sums over even and odd l - m.
    struct Task {
        int group, block;
    };
    std::vector<Task> tasks;
    for (std::size_t g = 0; g < groups.size(); ++g) {
        for (std::size_t k = groups[g].first; k < groups[g].end; ++k)
            result.levels[k].texels.resize(std::size_t(groups[g].width) * std::size_t(groups[g].height));
        for (int block = 0; block < groups[g].blocks; ++block) tasks.push_back({int(g), block});
    }
    std::reverse(tasks.begin(), tasks.end());  // the widest grids first
    tbb::parallel_for(0, int(tasks.size()), [&](int t) {
        const Group& group = groups[std::size_t(tasks[std::size_t(t)].group)];
        const int block = tasks[std::size_t(t)].block, width = group.width, height = group.height;
        const int levels = int(group.end - group.first);
        ThreadScratch& local = local_scratch();
        alignas(64) double x[kBlock], s[kBlock];
        for (int b = 0; b < kBlock; ++b) {
            const int j = std::min(block * kBlock + b, group.north - 1);
            const double theta = kPi * j / (height - 1);  // rows from pole to pole (prefilter.h)
            x[b] = std::cos(theta);
            s[b] = std::sin(theta);
        }
        double* pmm = local.pmm.get();
        sectoral(recurrence, s, group.band, pmm);
        const int last_order = last_nonzero_order(pmm, group.band);

        // Per level and channel one complex row per lane: the northern row in the real part, the southern one in
        // the imaginary part (two real rows through one transform, as in the analysis).
        // [level][channel][re/im][i][lane].
        const std::size_t row_size = std::size_t(width) * kBlock;
        double* rows = local.rows.get();
        auto row_re = [&](int g, int c) { return rows + std::size_t((g * 3 + c) * 2) * row_size; };
        for (int g = 0; g < levels; ++g) {  // orders above the level's band (or underflowed) are zero
            const int zero_from = std::min(plans[group.first + std::size_t(g)].band, last_order) + 1;
            for (int c = 0; c < 3; ++c) {
                double* re = row_re(g, c);
                std::fill(re + std::size_t(zero_from) * kBlock, re + std::size_t(width - zero_from + 1) * kBlock, 0.0);
                std::fill(re + row_size + std::size_t(zero_from) * kBlock,
                          re + row_size + std::size_t(width - zero_from + 1) * kBlock, 0.0);
            }
        }
        double* legendre = local.legendre.get();
        for (int m = 0; m <= last_order; ++m) {
            order_legendre(recurrence, x, &pmm[std::size_t(m) * kBlock], m, group.band, legendre);
            const double* c_m = &coefficients[recurrence.offset(m) * 6];
            for (int g = 0; g < levels; ++g) {
                const LevelPlan& plan = plans[group.first + std::size_t(g)];
                if (m > plan.band) continue;
                alignas(64) double sums[2][6][kBlock];
                degree_sums(legendre, c_m, plan.factors.data() + m, m, plan.band, sums);
                // North X = (even + odd) e^{i pi m / W}, south Y = (even - odd) e^{i pi m / W}; the row
                // X_0 + 2 Re sum_{m > 0} X_m e^{i m phi} (X_0 real) is the transform of X_m at m and conj X_m
                // at W - m. Packed with Y: Z_m = X_m + i Y_m, Z_{W-m} = conj X_m + i conj Y_m.
                const double shift_re = group.shift_re[std::size_t(m)], shift_im = group.shift_im[std::size_t(m)];
                const std::size_t at_m = std::size_t(m) * kBlock, at_mirror = std::size_t(width - m) * kBlock;
                for (int c = 0; c < 3; ++c) {
                    double* re = row_re(g, c);
                    double* im = re + row_size;
                    for (int b = 0; b < kBlock; ++b) {
                        const double er = sums[0][2 * c][b], ei = sums[0][2 * c + 1][b];
                        const double or_ = sums[1][2 * c][b], oi = sums[1][2 * c + 1][b];
                        const double nr = er + or_, ni = ei + oi, sr = er - or_, si = ei - oi;
                        const double xr = nr * shift_re - ni * shift_im, xi = nr * shift_im + ni * shift_re;
                        const double yr = sr * shift_re - si * shift_im, yi = sr * shift_im + si * shift_re;
                        if (m == 0) {
                            re[b] = xr;
                            im[b] = yr;
                        } else {
                            re[at_m + std::size_t(b)] = xr - yi;
                            im[at_m + std::size_t(b)] = xi + yr;
                            re[at_mirror + std::size_t(b)] = xr + yi;
                            im[at_mirror + std::size_t(b)] = yr - xi;
                        }
                    }
                }
            }
        }
        for (int g = 0; g < levels; ++g) {
            for (int c = 0; c < 3; ++c) block_fft(group.fft, row_re(g, c), row_re(g, c) + row_size, 1.0);
            PrefilteredLevel& level = result.levels[group.first + std::size_t(g)];
            const double* re[3] = {row_re(g, 0), row_re(g, 1), row_re(g, 2)};
            const int rows_here = std::min(kBlock, group.north - block * kBlock);
            glm::vec3* north_texels[kBlock];
            glm::vec3* south_texels[kBlock];  // null for a middle row, its own mirror
            for (int b = 0; b < rows_here; ++b) {
                const int north_row = block * kBlock + b, south_row = height - 1 - north_row;
                north_texels[b] = &level.texels[std::size_t(north_row) * std::size_t(width)];
                south_texels[b] =
                    south_row != north_row ? &level.texels[std::size_t(south_row) * std::size_t(width)] : nullptr;
            }
            for (int i = 0; i < width; ++i) {  // the transforms' output is bit-reversed
                const std::size_t at = std::size_t(group.fft.reversed[std::size_t(i)]) * kBlock;
                auto texel = [&](std::size_t from) {  // the truncated expansion may ring a little below zero
                    return glm::vec3(float(std::max(re[0][from], 0.0)), float(std::max(re[1][from], 0.0)),
                                     float(std::max(re[2][from], 0.0)));
                };
                for (int b = 0; b < rows_here; ++b) {
                    north_texels[b][i] = texel(at + std::size_t(b));
                    if (south_texels[b]) south_texels[b][i] = texel(at + std::size_t(b) + row_size);
                }
            }
        }
    });
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace envshadow
