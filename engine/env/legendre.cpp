#include "env/legendre.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace envshadow::prefiltering {
namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

LegendreRecurrence::LegendreRecurrence(int max_degree)
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

void sectoral(const LegendreRecurrence& recurrence, const double* s, int last, double* pmm) {
    for (int b = 0; b < kBlock; ++b) pmm[b] = std::sqrt(1.0 / (4.0 * kPi));
    for (int m = 1; m <= last; ++m)
        for (int b = 0; b < kBlock; ++b)
            pmm[std::size_t(m) * kBlock + std::size_t(b)] =
                recurrence.sectoral_factor[std::size_t(m)] * s[b] * pmm[std::size_t(m - 1) * kBlock + std::size_t(b)];
}

int last_nonzero_order(const double* pmm, int last) {
    while (last > 0 && std::all_of(pmm + std::size_t(last) * kBlock, pmm + std::size_t(last + 1) * kBlock,
                                   [](double p) { return p == 0.0; }))
        --last;
    return last;
}

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

}  // namespace envshadow::prefiltering
