// Prefiltering the environment for the ratio estimator (docs/DESIGN.md §4.1) through spherical harmonics.
// With Y_lm = P_lm(cos theta) e^{i m phi} orthonormal, the map's coefficients are the exact texel sums
//   c_lm = sum over texels of L dw P_lm(cos theta) e^{-i m phi}
// (so the result is the direct numerical integral of the texels, the twin test's truth, up to the
// truncation of the lobe's expansion), and by Funk-Hecke any lobe K(r . w) gives
//   integral of L K(r . w) dw = sum_lm Lambda_l c_lm Y_lm(r),  Lambda_l = 2 pi integral K(t) P_l(t) dt.
// The Phong lobe's Lambda_l falls like exp(-l^2 / 2n), so level n needs l up to ~4.5 sqrt(n); its grid
// follows the lobe's width (texel spacing ~ a quarter of 1 / sqrt(n), where bilinear lookups err < 1%).
#include "env/prefilter.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>

#include "env/latlong.h"

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

// In-place radix-2 FFT, sum_k a_k e^{sign 2 pi i j k / N}; N a power of two.
void fft(std::vector<Complex>& a, int sign) {
    const std::size_t n = a.size();
    for (std::size_t i = 1, j = 0; i < n; ++i) {
        std::size_t bit = n >> 1;
        for (; j & bit; bit >>= 1) j ^= bit;
        j ^= bit;
        if (i < j) std::swap(a[i], a[j]);
    }
    for (std::size_t len = 2; len <= n; len <<= 1) {
        const double angle = sign * 2.0 * kPi / double(len);
        for (std::size_t k = 0; k < len / 2; ++k) {
            const Complex w(std::cos(angle * double(k)), std::sin(angle * double(k)));
            for (std::size_t i = k; i < n; i += len) {
                const Complex u = a[i], v = a[i + len / 2] * w;
                a[i] = u + v;
                a[i + len / 2] = u - v;
            }
        }
    }
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
void along_degree(const LegendreRecurrence& r, const double* x, const double* pmm, int m, int lmax, Visit&& visit) {
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

int next_power_of_two(int x) {
    return int(std::bit_ceil(unsigned(std::max(x, 1))));
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
    const EnvironmentMap map = resampled(full_map);
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
    std::vector<double> spectra(std::size_t(blocks) * std::size_t(bands) * 6 * kBlock, 0.0);
    std::vector<double> block_x(std::size_t(blocks) * kBlock, 0.0), block_s(block_x.size(), 0.0);
    const bool power_of_two = std::has_single_bit(unsigned(w));
    tbb::parallel_for(0, int(rows_used.size()), [&](int r) {
        const int j = rows_used[std::size_t(r)];
        const double dw = hemisphere_texel_solid_angle(j, w, h, hemisphere);
        const int block = r / kBlock, lane = r % kBlock;
        block_x[std::size_t(r)] = std::cos(kPi * (j + 0.5) / h);
        block_s[std::size_t(r)] = std::sin(kPi * (j + 0.5) / h);
        std::vector<Complex> row(static_cast<std::size_t>(w));
        for (int c = 0; c < 3; ++c) {
            for (int m = 0; m < bands; ++m) {
                Complex value;
                if (power_of_two) {
                    if (m == 0) {
                        for (int i = 0; i < w; ++i) row[std::size_t(i)] = map.at(i, j)[c];
                        fft(row, -1);
                    }
                    value = row[std::size_t(m)];
                } else {
                    for (int i = 0; i < w; ++i)
                        value += double(map.at(i, j)[c]) * std::polar(1.0, -2.0 * kPi * m * i / w);
                }
                value *= dw * std::polar(1.0, -kPi * m / w);
                double* out = &spectra[((std::size_t(block) * std::size_t(bands) + std::size_t(m)) * 6) * kBlock];
                out[(2 * c) * kBlock + lane] = value.real();
                out[(2 * c + 1) * kBlock + lane] = value.imag();
            }
        }
    });

    // c_lm = sum_j P_lm(cos theta_j) F_j(m), one task per order m; 6 doubles per coefficient.
    std::vector<double> coefficients((coefficient_index(lmax, lmax) + 1) * 6, 0.0);
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
        for (int block = 0; block < blocks; ++block) {
            const double* f = &spectra[((std::size_t(block) * std::size_t(bands) + std::size_t(m)) * 6) * kBlock];
            const double* pmm = &block_pmm[(std::size_t(block) * std::size_t(bands) + std::size_t(m)) * kBlock];
            along_degree(recurrence, &block_x[std::size_t(block) * kBlock], pmm, m, lmax, [&](int l, const double* p) {
                double* c = &coefficients[coefficient_index(l, m) * 6];
                for (int q = 0; q < 6; ++q) {
                    double sum = 0.0;
                    for (int b = 0; b < kBlock; ++b) sum += p[b] * f[q * kBlock + b];
                    c[q] += sum;
                }
            });
        }
    });

    // Each level: G_m(theta) = sum_l Lambda_l c_lm P_lm(cos theta), then each row by an inverse FFT of
    // G_0 + 2 sum_{m > 0} G_m e^{i m phi}. kBlock rows at a time.
    for (std::size_t k = 0; k < result.levels.size(); ++k) {
        PrefilteredLevel& level = result.levels[k];
        const LevelPlan& plan = plans[k];
        level.texels.resize(std::size_t(level.width) * std::size_t(level.height));
        // Rows j and H - 1 - j mirror each other (x -> -x): P_lm(-x) = (-1)^{l+m} P_lm(x), so the northern
        // half's recurrence gives both, from the sums over even and odd l - m.
        const int north = (level.height + 1) / 2;
        const int level_blocks = (north + kBlock - 1) / kBlock;
        tbb::parallel_for(0, level_blocks, [&](int block) {
            alignas(64) double x[kBlock], pmm_m[kBlock];
            std::vector<std::vector<double>> pmm(kBlock);
            for (int b = 0; b < kBlock; ++b) {
                const int j = std::min(block * kBlock + b, north - 1);
                const double theta = kPi * j / (level.height - 1);  // rows from pole to pole (prefilter.h)
                x[b] = std::cos(theta);
                sectoral(std::sin(theta), plan.band, pmm[std::size_t(b)]);
            }
            // [hemisphere: 0 north, 1 south][lane][channel]
            std::vector<std::vector<Complex>> rows(std::size_t(2 * kBlock) * 3,
                                                   std::vector<Complex>(std::size_t(level.width)));
            for (int m = 0; m <= plan.band; ++m) {
                alignas(64) double g[2][6][kBlock] = {};  // [parity of l - m][re/im x rgb][lane]
                for (int b = 0; b < kBlock; ++b) pmm_m[b] = pmm[std::size_t(b)][std::size_t(m)];
                along_degree(recurrence, x, pmm_m, m, plan.band, [&](int l, const double* p) {
                    const double factor = plan.factors[std::size_t(l)];
                    const double* c = &coefficients[coefficient_index(l, m) * 6];
                    double(&gp)[6][kBlock] = g[(l - m) & 1];
                    for (int q = 0; q < 6; ++q) {
                        const double cq = c[q] * factor;
                        for (int b = 0; b < kBlock; ++b) gp[q][b] += p[b] * cq;
                    }
                });
                const Complex shift = std::polar(m == 0 ? 1.0 : 2.0, kPi * m / level.width);
                for (int b = 0; b < kBlock; ++b)
                    for (int c = 0; c < 3; ++c) {
                        const Complex even(g[0][2 * c][b], g[0][2 * c + 1][b]), odd(g[1][2 * c][b], g[1][2 * c + 1][b]);
                        rows[std::size_t(b) * 3 + std::size_t(c)][std::size_t(m)] = (even + odd) * shift;
                        rows[std::size_t(kBlock + b) * 3 + std::size_t(c)][std::size_t(m)] = (even - odd) * shift;
                    }
            }
            for (int half = 0; half < 2; ++half)
                for (int b = 0; b < kBlock; ++b) {
                    const int north_row = block * kBlock + b;
                    if (north_row >= north) break;
                    const int j = half == 0 ? north_row : level.height - 1 - north_row;
                    for (int c = 0; c < 3; ++c) {
                        std::vector<Complex>& row = rows[std::size_t(half * kBlock + b) * 3 + std::size_t(c)];
                        fft(row, +1);
                        for (int i = 0; i < level.width; ++i)  // the truncated expansion may ring a little below zero
                            level.texels[std::size_t(j) * std::size_t(level.width) + std::size_t(i)][c] =
                                float(std::max(row[std::size_t(i)].real(), 0.0));
                    }
                }
        });
    }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace envshadow
