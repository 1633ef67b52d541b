#pragma once
// Associated Legendre functions for the prefiltering's spherical harmonics (env/prefilter.cpp; internal to
// it): the recurrences' factors, and the kernels that project a block of rows' spectra onto P_lm and
// sum a level's degrees back, kBlock rows (lanes) at a time.
#include <cstddef>
#include <vector>

#include "env/row_block.h"

namespace envshadow::prefiltering {

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
    explicit LegendreRecurrence(int max_degree);
};

// P_mm(s) of kBlock rows for m = 0..last, at pmm[m * kBlock + b].
void sectoral(const LegendreRecurrence& recurrence, const double* s, int last, double* pmm);

// The highest order whose sectoral value has not underflowed to zero in some lane: above it, every P_lm of the
// block is zero (the recurrences start from P_mm), near the poles where sin theta is small.
int last_nonzero_order(const double* pmm, int last);

// c_lm = sum over row pairs of P_lm(x) (E_m if l - m is even, O_m if odd: the pair's even and odd spectra) for
// one order m, l = m..lmax, into c[(l - m) * 6 + q]. Degree by degree, every block's recurrence advanced one step
// (state in p1, p2): the blocks are independent chains, and the sums stay in registers per lane, reduced across
// lanes once per degree; four lanes at a time. The blocks nearest the pole whose sectoral values underflowed to
// zero add nothing and are skipped.
void order_coefficients(const LegendreRecurrence& recurrence, int m, int blocks, int bands, int parities,
                        const double* spectra, const double* block_x, const double* block_pmm, double* p1, double* p2,
                        double* c);

// P_lm(x_b) of one block of rows for l = m..last, at legendre[(l - m) * kBlock + b]: the block's two vectors are
// two independent dependency chains.
void order_legendre(const LegendreRecurrence& recurrence, const double* x, const double* pmm, int m, int last,
                    double* legendre);

// For one order m and one block of rows: sums[parity of l - m][re/im x rgb][lane] = sum over l = m..band of that
// parity of factors[l - m] c[(l - m) * 6 + q] P_lm(x_lane) (the level's Funk-Hecke factors times the order's
// coefficients). Four lanes at a time, so that the twelve accumulators (six sums, two parities), the two
// Legendre vectors and a broadcast fit the 16 vector registers.
void degree_sums(const double* legendre, const double* c, const double* factors, int m, int band,
                 double (&sums)[2][6][kBlock]);

}  // namespace envshadow::prefiltering
