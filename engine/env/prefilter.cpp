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
#include <numbers>

#include "env/latlong.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace envshadow {
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

// Radix-2 FFT, a_j -> sum_k a_k e^{sign 2 pi i j k / N}, in place on split real and imaginary parts, with
// the twiddles tabled once per size (the rows of a level all share one size).
class Fft {
public:
    explicit Fft(int n) : n_(n), reversed_(std::size_t(n)), cos_(std::size_t(std::max(n - 1, 1))), sin_(cos_.size()) {
        for (int i = 0, j = 0; i < n; ++i) {
            reversed_[std::size_t(i)] = j;
            int bit = n >> 1;
            for (; j & bit; bit >>= 1) j ^= bit;
            j ^= bit;
        }
        for (int half = 1; half < n; half <<= 1)  // the stage of half-length h: entries h - 1 .. 2h - 2
            for (int k = 0; k < half; ++k) {
                cos_[std::size_t(half - 1 + k)] = std::cos(kPi * k / half);
                sin_[std::size_t(half - 1 + k)] = std::sin(kPi * k / half);
            }
    }
    void transform(double* re, double* im, int sign) const {
        for (int i = 0; i < n_; ++i) {
            const int j = reversed_[std::size_t(i)];
            if (i < j) std::swap(re[i], re[j]), std::swap(im[i], im[j]);
        }
        for (int half = 1; half < n_; half <<= 1) {
            const double* wr = &cos_[std::size_t(half - 1)];
            const double* ws = &sin_[std::size_t(half - 1)];
            for (int start = 0; start < n_; start += 2 * half) {
                double *ar = re + start, *ai = im + start, *br = re + start + half, *bi = im + start + half;
                for (int k = 0; k < half; ++k) {
                    const double wi = sign * ws[k];
                    const double vr = br[k] * wr[k] - bi[k] * wi, vi = br[k] * wi + bi[k] * wr[k];
                    br[k] = ar[k] - vr, bi[k] = ai[k] - vi;
                    ar[k] += vr, ai[k] += vi;
                }
            }
        }
    }

private:
    int n_;
    std::vector<int> reversed_;
    std::vector<double> cos_, sin_;
};

// `values` resized to `count` (zeros), on transparent huge pages where the kernel offers them (THP in
// madvise mode): the levels and spectra are written once, tens of MB, and touching them 4 KiB page by page
// cost ~13 us a page on the measuring VM, a third of the prefiltering (docs/PERFORMANCE.md).
template <class T>
void resize_on_huge_pages(std::vector<T>& values, std::size_t count) {
    values.reserve(count);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr std::uintptr_t kHugePage = std::uintptr_t(2) << 20;
    const auto first = (reinterpret_cast<std::uintptr_t>(values.data()) + kHugePage - 1) & ~(kHugePage - 1);
    const auto last = reinterpret_cast<std::uintptr_t>(values.data() + count) & ~(kHugePage - 1);
    if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);  // advice only
#endif
    values.resize(count);
}

int next_power_of_two(int x) {
    return int(std::bit_ceil(unsigned(std::max(x, 1))));
}

std::size_t coefficient_index(int l, int m) {
    return std::size_t(l) * std::size_t(l + 1) / 2 + std::size_t(m);
}

// Orthonormal associated Legendre functions (no Condon-Shortley phase) by the standard stable recurrences:
//   P_mm = sqrt((2m+1)/(2m)) s P_{m-1,m-1},  P_{m+1,m} = sqrt(2m+3) x P_mm,
//   P_lm = a_lm (x P_{l-1,m} - b_lm P_{l-2,m}).
struct LegendreRecurrence {
    std::vector<double> a, b;  // by coefficient_index(l, m)
    explicit LegendreRecurrence(int lmax) : a(coefficient_index(lmax, lmax) + 1), b(a.size()) {
        for (int l = 2; l <= lmax; ++l)
            for (int m = 0; m <= l - 2; ++m) {
                const double l2 = double(l) * l, m2 = double(m) * m, lm1 = double(l - 1) * (l - 1);
                a[coefficient_index(l, m)] = std::sqrt((4.0 * l2 - 1.0) / (l2 - m2));
                b[coefficient_index(l, m)] = std::sqrt((lm1 - m2) / (4.0 * lm1 - 1.0));
            }
    }
};

// P_mm(cos theta) for m = 0..lmax.
void sectoral(double s, int lmax, std::vector<double>& pmm) {
    pmm.resize(std::size_t(lmax) + 1);
    pmm[0] = std::sqrt(1.0 / (4.0 * kPi));
    for (int m = 1; m <= lmax; ++m)
        pmm[std::size_t(m)] = std::sqrt((2.0 * m + 1.0) / (2.0 * m)) * s * pmm[std::size_t(m - 1)];
}

// Calls visit(l, p) with p[b] = P_lm(x[b]) for l = m..lmax, kBlock rows at once: the recurrence's
// latency is shared by the rows and the per-row work vectorises.
constexpr int kBlock = 8;
template <class Visit>
[[gnu::always_inline]] inline void along_degree(const LegendreRecurrence& r, const double* x, const double* pmm, int m,
                                                int lmax, Visit&& visit) {
    alignas(64) double p2[kBlock], p1[kBlock], p[kBlock];
    for (int b = 0; b < kBlock; ++b) p1[b] = pmm[b];
    visit(m, p1);
    if (m + 1 > lmax) return;
    const double start = std::sqrt(2.0 * m + 3.0);
    for (int b = 0; b < kBlock; ++b) p[b] = start * x[b] * pmm[b];
    visit(m + 1, p);
    for (int b = 0; b < kBlock; ++b) p2[b] = p1[b], p1[b] = p[b];
    for (int l = m + 2; l <= lmax; ++l) {
        const std::size_t k = coefficient_index(l, m);
        const double a = r.a[k], bb = r.b[k];
        for (int b = 0; b < kBlock; ++b) p[b] = a * (x[b] * p1[b] - bb * p2[b]);
        visit(l, p);
        for (int b = 0; b < kBlock; ++b) p2[b] = p1[b], p1[b] = p[b];
    }
}

// The hot loops below are compiled twice, for the baseline x86-64 and for AVX2 (4 doubles a vector instead of
// 2), and the processor picks one at load time; elsewhere once.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define ENVSHADOW_VECTOR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define ENVSHADOW_VECTOR_CLONES
#endif

// c_lm = sum_j P_lm(cos theta_j) F_j(m) for one order m, l = m..lmax, into by_degree[(l - m) * 6 + q]. Degree
// by degree, every block's recurrence advanced one step (state in p1, p2), so that the sums over the rows
// stay in registers per lane and are reduced across lanes once per degree.
ENVSHADOW_VECTOR_CLONES
void order_coefficients(const LegendreRecurrence& recurrence, int m, int lmax, int blocks, int bands,
                        const double* spectra, const double* block_x, const double* block_pmm, double* by_degree) {
    std::vector<double> p1(std::size_t(blocks) * kBlock), p2(p1.size());  // P_{l-1,m}, P_{l-2,m} per row
    const double start = std::sqrt(2.0 * m + 3.0);
    for (int l = m; l <= lmax; ++l) {
        const std::size_t k = l >= m + 2 ? coefficient_index(l, m) : 0;
        const double a = recurrence.a[k], bb = recurrence.b[k];
        alignas(64) double sum[6][kBlock] = {};
        for (int block = 0; block < blocks; ++block) {
            const double* f = &spectra[((std::size_t(block) * std::size_t(bands) + std::size_t(m)) * 6) * kBlock];
            const double* x = &block_x[std::size_t(block) * kBlock];
            double* q1 = &p1[std::size_t(block) * kBlock];
            double* q2 = &p2[std::size_t(block) * kBlock];
            alignas(64) double p[kBlock];
            if (l == m) {
                const double* pmm = &block_pmm[(std::size_t(block) * std::size_t(bands) + std::size_t(m)) * kBlock];
                for (int b = 0; b < kBlock; ++b) p[b] = pmm[b];
            } else if (l == m + 1) {
                for (int b = 0; b < kBlock; ++b) p[b] = start * x[b] * q1[b];
            } else {
                for (int b = 0; b < kBlock; ++b) p[b] = a * (x[b] * q1[b] - bb * q2[b]);
            }
            for (int b = 0; b < kBlock; ++b) q2[b] = q1[b], q1[b] = p[b];
            for (int q = 0; q < 6; ++q)
                for (int b = 0; b < kBlock; ++b) sum[q][b] += p[b] * f[q * kBlock + b];
        }
        for (int q = 0; q < 6; ++q) {
            double total = 0.0;
            for (int b = 0; b < kBlock; ++b) total += sum[q][b];
            by_degree[std::size_t(l - m) * 6 + std::size_t(q)] = total;
        }
    }
}

// P_lm(x_b) for l = m..lmax of one block of rows, at legendre[(l - m) * kBlock + b].
ENVSHADOW_VECTOR_CLONES
void order_legendre(const LegendreRecurrence& recurrence, const double* x, const double* pmm, int m, int lmax,
                    double* legendre) {
    along_degree(recurrence, x, pmm, m, lmax,
                 [&](int l, const double* p) { std::copy(p, p + kBlock, &legendre[std::size_t(l - m) * kBlock]); });
}

// For one order m and one block of rows: sums[parity of l - m][re/im x rgb][lane] = sum over l = m..band of
// that parity of factors[l] c_lm P_lm(x_lane), with c_lm at c[(l - m) * 6]. Three of the six sums at a time,
// so that they stay in registers.
ENVSHADOW_VECTOR_CLONES
void degree_sums(const double* legendre, const double* c, const double* factors, int m, int band,
                 double (&sums)[2][6][kBlock]) {
    for (int parity = 0; parity < 2; ++parity)
        for (int first = 0; first < 6; first += 3) {
            alignas(64) double sum[3][kBlock] = {};
            for (int l = m + parity; l <= band; l += 2) {
                const double factor = factors[l];
                const double* cl = c + std::size_t(l - m) * 6 + first;
                const double c0 = cl[0] * factor, c1 = cl[1] * factor, c2 = cl[2] * factor;
                const double* p = &legendre[std::size_t(l - m) * kBlock];
                for (int b = 0; b < kBlock; ++b) {
                    sum[0][b] += p[b] * c0;
                    sum[1][b] += p[b] * c1;
                    sum[2][b] += p[b] * c2;
                }
            }
            for (int q = 0; q < 3; ++q)
                for (int b = 0; b < kBlock; ++b) sums[parity][first + q][b] = sum[q][b];
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

    // Row spectra of L dw: F_j(m) = dw_j sum_i L_ij e^{-i m phi_i}, phi_i = 2 pi (i + 0.5) / W; as 6 doubles
    // (re, im of r, g, b) per row and order. Rows outside the hemisphere are left out.
    const int bands = lmax + 1;
    std::vector<int> rows_used;
    for (int j = 0; j < h; ++j)
        if (hemisphere_texel_solid_angle(j, w, h, hemisphere) > 0.0) rows_used.push_back(j);
    const int blocks = (int(rows_used.size()) + kBlock - 1) / kBlock;
    // Per block of kBlock rows and order m: [6][kBlock] doubles; padding rows are zero.
    std::vector<double> spectra;
    resize_on_huge_pages(spectra, std::size_t(blocks) * std::size_t(bands) * 6 * kBlock);
    std::vector<double> block_x(std::size_t(blocks) * kBlock, 0.0), block_s(block_x.size(), 0.0);
    std::vector<Complex> source_shift(static_cast<std::size_t>(bands));  // e^{-i pi m / W}: phi_i's half texel
    for (int m = 0; m < bands; ++m) source_shift[std::size_t(m)] = std::polar(1.0, -kPi * m / w);
    const bool power_of_two = std::has_single_bit(unsigned(w));
    const Fft source_fft(power_of_two ? w : 1);
    tbb::parallel_for(0, int(rows_used.size()), [&](int r) {
        const int j = rows_used[std::size_t(r)];
        const double dw = hemisphere_texel_solid_angle(j, w, h, hemisphere);
        const int block = r / kBlock, lane = r % kBlock;
        block_x[std::size_t(r)] = std::cos(kPi * (j + 0.5) / h);
        block_s[std::size_t(r)] = std::sin(kPi * (j + 0.5) / h);
        auto store = [&](int m, int c, Complex value) {
            value *= dw * source_shift[std::size_t(m)];
            double* out = &spectra[((std::size_t(block) * std::size_t(bands) + std::size_t(m)) * 6) * kBlock];
            out[(2 * c) * kBlock + lane] = value.real();
            out[(2 * c + 1) * kBlock + lane] = value.imag();
        };
        if (power_of_two) {
            // Red and green through one transform of r + i g: Z_m = X_m + i Y_m with X, Y the spectra of
            // real rows (X_{-m} = conj X_m), so X_m = (Z_m + conj Z_{-m}) / 2, Y_m = (Z_m - conj Z_{-m}) / 2i.
            std::vector<double> re(std::size_t(w) * 2), im(std::size_t(w) * 2, 0.0);  // [r + i g, b]
            for (int i = 0; i < w; ++i) {
                const glm::vec3 texel = map.at(i, j);
                re[std::size_t(i)] = texel.r, im[std::size_t(i)] = texel.g, re[std::size_t(w + i)] = texel.b;
            }
            source_fft.transform(re.data(), im.data(), -1);
            source_fft.transform(re.data() + w, im.data() + w, -1);
            for (int m = 0; m < bands; ++m) {
                const std::size_t p = std::size_t(m), q = std::size_t((w - m) % w);
                store(m, 0, 0.5 * Complex(re[p] + re[q], im[p] - im[q]));
                store(m, 1, 0.5 * Complex(im[p] + im[q], re[q] - re[p]));
                store(m, 2, Complex(re[std::size_t(w) + p], im[std::size_t(w) + p]));
            }
        } else {
            for (int c = 0; c < 3; ++c)
                for (int m = 0; m < bands; ++m) {
                    Complex value;
                    for (int i = 0; i < w; ++i)
                        value += double(map.at(i, j)[c]) * std::polar(1.0, -2.0 * kPi * m * i / w);
                    store(m, c, value);
                }
        }
    });

    // c_lm = sum_j P_lm(cos theta_j) F_j(m), one task per order m; 6 doubles per coefficient, by order:
    // coefficients[m][(l - m) * 6 + q].
    std::vector<std::vector<double>> coefficients(static_cast<std::size_t>(bands));
    std::vector<double> block_pmm(std::size_t(blocks) * kBlock * std::size_t(bands));  // [block][m][lane]
    tbb::parallel_for(0, blocks, [&](int block) {
        std::vector<double> pmm;
        for (int lane = 0; lane < kBlock; ++lane) {
            sectoral(block_s[std::size_t(block * kBlock + lane)], lmax, pmm);
            for (int m = 0; m < bands; ++m)
                block_pmm[(std::size_t(block) * std::size_t(bands) + std::size_t(m)) * kBlock + std::size_t(lane)] =
                    pmm[std::size_t(m)];
        }
    });
    tbb::parallel_for(0, bands, [&](int m) {
        std::vector<double>& by_degree = coefficients[std::size_t(m)];
        by_degree.assign(std::size_t(lmax + 1 - m) * 6, 0.0);
        order_coefficients(recurrence, m, lmax, blocks, bands, spectra.data(), block_x.data(), block_pmm.data(),
                           by_degree.data());
    });

    // Each level: G_m(theta) = sum_l Lambda_l c_lm P_lm(cos theta), then each row by an inverse FFT of
    // G_0 + 2 sum_{m > 0} G_m e^{i m phi}. kBlock rows at a time; the levels of one grid size share the
    // rows' Legendre recurrences (up to the group's largest band), so they are synthesised together.
    for (std::size_t first_level = 0; first_level < result.levels.size();) {
        std::size_t end_level = first_level + 1;
        while (end_level < result.levels.size() && result.levels[end_level].width == result.levels[first_level].width)
            ++end_level;
        const int width = result.levels[first_level].width, height = result.levels[first_level].height;
        const int group = int(end_level - first_level);
        int group_band = 0;
        for (std::size_t k = first_level; k < end_level; ++k) {
            group_band = std::max(group_band, plans[k].band);
            resize_on_huge_pages(result.levels[k].texels, std::size_t(width) * std::size_t(height));
        }
        const Fft level_fft(width);
        std::vector<Complex> level_shift(static_cast<std::size_t>(group_band) + 1);  // e^{i pi m / W}
        for (int m = 0; m <= group_band; ++m) level_shift[std::size_t(m)] = std::polar(1.0, kPi * m / width);
        // Rows j and H - 1 - j mirror each other (x -> -x): P_lm(-x) = (-1)^{l+m} P_lm(x), so the northern
        // half's recurrence gives both, from the sums over even and odd l - m.
        const int north = (height + 1) / 2;
        const int level_blocks = (north + kBlock - 1) / kBlock;
        const std::size_t row_values = std::size_t(group) * 3 * kBlock * std::size_t(width);
        // Per level, channel and lane one complex row: the northern row in the real part, the southern one in
        // the imaginary part (two real rows through one transform, as in the analysis). [level][channel][lane][i]
        tbb::enumerable_thread_specific<std::vector<double>> real_rows(row_values, 0.0),
            imaginary_rows(row_values, 0.0);
        tbb::parallel_for(0, level_blocks, [&](int block) {
            alignas(64) double x[kBlock], pmm_m[kBlock];
            std::vector<std::vector<double>> pmm(kBlock);
            for (int b = 0; b < kBlock; ++b) {
                const int j = std::min(block * kBlock + b, north - 1);
                const double theta = kPi * j / (height - 1);  // rows from pole to pole (prefilter.h)
                x[b] = std::cos(theta);
                sectoral(std::sin(theta), group_band, pmm[std::size_t(b)]);
            }
            double* re = real_rows.local().data();
            double* im = imaginary_rows.local().data();
            auto row_of = [&](int level, int channel, int lane) {
                return (std::size_t(level * 3 + channel) * kBlock + std::size_t(lane)) * std::size_t(width);
            };
            for (int g = 0; g < group; ++g)  // orders above the level's band are zero (the transforms overwrite)
                for (int c = 0; c < 3; ++c)
                    for (int b = 0; b < kBlock; ++b) {
                        const std::size_t row = row_of(g, c, b), band = std::size_t(plans[first_level + g].band);
                        std::fill(re + row + band + 1, re + row + std::size_t(width) - band, 0.0);
                        std::fill(im + row + band + 1, im + row + std::size_t(width) - band, 0.0);
                    }
            std::vector<double> legendre(std::size_t(group_band + 1) * kBlock);
            for (int m = 0; m <= group_band; ++m) {
                for (int b = 0; b < kBlock; ++b) pmm_m[b] = pmm[std::size_t(b)][std::size_t(m)];
                order_legendre(recurrence, x, pmm_m, m, group_band, legendre.data());
                for (int g = 0; g < group; ++g) {
                    const LevelPlan& plan = plans[first_level + std::size_t(g)];
                    if (m > plan.band) continue;
                    alignas(64) double sums[2][6][kBlock];
                    degree_sums(legendre.data(), coefficients[std::size_t(m)].data(), plan.factors.data(), m, plan.band,
                                sums);
                    // North X = (even + odd) e^{i pi m / W}, south Y = (even - odd) e^{i pi m / W}; the row
                    // X_0 + 2 Re sum_{m > 0} X_m e^{i m phi} (X_0 real) is the transform of X_m at m and conj X_m
                    // at W - m. Packed with Y: Z_m = X_m + i Y_m, Z_{W-m} = conj X_m + i conj Y_m.
                    const Complex shift = level_shift[std::size_t(m)];
                    for (int c = 0; c < 3; ++c)
                        for (int b = 0; b < kBlock; ++b) {
                            const Complex even(sums[0][2 * c][b], sums[0][2 * c + 1][b]);
                            const Complex odd(sums[1][2 * c][b], sums[1][2 * c + 1][b]);
                            const Complex north_value = (even + odd) * shift, south_value = (even - odd) * shift;
                            const std::size_t row = row_of(g, c, b);
                            if (m == 0) {
                                re[row] = north_value.real();
                                im[row] = south_value.real();
                            } else {
                                re[row + std::size_t(m)] = north_value.real() - south_value.imag();
                                im[row + std::size_t(m)] = north_value.imag() + south_value.real();
                                re[row + std::size_t(width - m)] = north_value.real() + south_value.imag();
                                im[row + std::size_t(width - m)] = south_value.real() - north_value.imag();
                            }
                        }
                }
            }
            for (int g = 0; g < group; ++g) {
                PrefilteredLevel& level = result.levels[first_level + std::size_t(g)];
                for (int b = 0; b < kBlock; ++b) {
                    const int north_row = block * kBlock + b;
                    if (north_row >= north) break;
                    const int south_row = height - 1 - north_row;
                    glm::vec3* north_texels = &level.texels[std::size_t(north_row) * std::size_t(width)];
                    glm::vec3* south_texels = &level.texels[std::size_t(south_row) * std::size_t(width)];
                    for (int c = 0; c < 3; ++c) {
                        const std::size_t row = row_of(g, c, b);
                        level_fft.transform(re + row, im + row, +1);
                        for (int i = 0; i < width; ++i) {  // the truncated expansion may ring a little below zero
                            north_texels[i][c] = float(std::max(re[row + std::size_t(i)], 0.0));
                            if (south_row != north_row)
                                south_texels[i][c] = float(std::max(im[row + std::size_t(i)], 0.0));
                        }
                    }
                }
            }
        });
        first_level = end_level;
    }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace envshadow
