#pragma once
// Fast Fourier transforms of blocks of rows for the prefiltering (env/prefilter.cpp; internal to it).
#include <vector>

#include "env/row_block.h"

namespace envshadow::prefiltering {

// Radix-2 FFT tables for size n: the bit reversal and the twiddles e^{i pi k / h} of each stage.
struct FftTables {
    int n = 0;
    std::vector<int> reversed;     // the input of index i goes to reversed[i]
    std::vector<double> cos, sin;  // the stage of half-length h: entries h - 1 .. 2h - 2
    explicit FftTables(int size);
};

// a_j -> sum_k a_k e^{sign 2 pi i j k / N} for kBlock rows at once, in place on split real and imaginary parts
// laid out [index][lane]: the input in natural order, the output in bit-reversed order (index j at
// FftTables::reversed[j]; the callers read it so). Decimation in frequency, two stages at a time (radix 2^2:
// four points loaded once for two stages' butterflies, so a block's 128 KB of rows at N = 1024 is swept five
// times instead of ten), the last two (twiddles 1 and +-i) without multiplications.
void block_fft(const FftTables& fft, double* re, double* im, double sign);

}  // namespace envshadow::prefiltering
