#include "env/fft.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

namespace envshadow::prefiltering {
namespace {

constexpr double kPi = std::numbers::pi;

// (a, b) -> (a + b, (a - b) w) in every lane: the decimation-in-frequency butterfly.
[[gnu::always_inline]] inline void butterfly(Vector& ar, Vector& ai, Vector& br, Vector& bi, double wr, double wi) {
    const Vector dr = ar - br, di = ai - bi;
    ar += br, ai += bi;
    br = dr * wr - di * wi, bi = dr * wi + di * wr;
}

}  // namespace

FftTables::FftTables(int size)
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

}  // namespace envshadow::prefiltering
