#pragma once
// The prefiltering's row blocks and their vectors (env/prefilter.cpp and its kernels env/fft.cpp,
// env/legendre.cpp; internal to them): rows are processed kBlock at a time, one lane each, in arrays laid
// out [..][lane], so that every inner loop is kBlock independent lanes (one or two SIMD vectors) with no
// horizontal sums, and the recurrences' latency is shared.
#include <cstring>

namespace envshadow::prefiltering {

constexpr int kBlock = 8;

// The hot loops are compiled twice, for the baseline x86-64 and for x86-64-v3 (AVX2 and FMA: 4 doubles a
// vector instead of 2, a * b + c in one rounding; their files are compiled with -ffp-contract=fast), and
// the processor picks one at load time.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define ENVSHADOW_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define ENVSHADOW_VECTOR_CLONES
#endif

// Four doubles with element-wise arithmetic (GCC and Clang vector extensions): one AVX2 register in the
// x86-64-v3 clones, two SSE2 ones in the baseline. A block's kBlock lanes are two of them; the kernels (fft.cpp,
// legendre.cpp) hold their accumulators and butterflies in such vectors so that they stay in the 16 registers.
constexpr int kVector = 4;
typedef double Vector __attribute__((vector_size(kVector * sizeof(double))));
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"  // Vector by value only between always-inlined helpers
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

}  // namespace envshadow::prefiltering
