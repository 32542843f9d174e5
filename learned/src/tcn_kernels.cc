#include "tcn_kernels.h"

#include <unsupported/Eigen/SpecialFunctions>

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#define HDVIO_TCN_AVX2 1
#endif

namespace hdvio::learned::detail {
namespace {

// kCols output columns x kRows output rows (starting at row o0) of accumulators. Rows of a
// 32-row block come from two panels. GCC vectorizes the row loop; the AVX2 + FMA copy of
// these templates is compiled with that target (runtime check), the default one for plain
// x86-64.
template <int kRows, int kCols, bool kFma>
inline __attribute__((always_inline)) void convolveBlock(const PackedConv& w, const float* const* x,
                                                         int first_tap, float* Y) {
  const int in = w.in, taps = w.taps;
  const long panel = static_cast<long>(taps) * in * kPanelRows;
  for (int o0 = 0; o0 < w.rows; o0 += kRows) {
    float acc[kCols][kRows] = {};
    const float* base = w.panels.data() + (o0 / kPanelRows) * panel + o0 % kPanelRows;
    for (int j = first_tap; j < taps; ++j) {
      const float* xs[kCols];
      for (int c = 0; c < kCols; ++c) xs[c] = x[c * taps + j];
      const float* wj = base + static_cast<long>(j) * in * kPanelRows;
      for (int i = 0; i < in; ++i) {
        const float* wi = wj + static_cast<long>(i) * kPanelRows;
#pragma GCC unroll 4
        for (int c = 0; c < kCols; ++c) {
          const float v = xs[c][i];
#pragma GCC unroll 32
          for (int o = 0; o < kRows; ++o) {
            const float wo = kRows > kPanelRows ? wi[(o / kPanelRows) * panel + o % kPanelRows] : wi[o];
            if constexpr (kFma) {
              acc[c][o] = __builtin_fmaf(wo, v, acc[c][o]);
            } else {
              acc[c][o] += wo * v;
            }
          }
        }
      }
    }
    for (int c = 0; c < kCols; ++c) {
      float* y = Y + static_cast<long>(c) * w.rows + o0;
      for (int o = 0; o < kRows; ++o) y[o] = acc[c][o] + w.bias[o0 + o];
    }
  }
}

// Blocks of kWide columns (kRows rows), then the remainder with kernels of its exact width
// (the last layers of a window need one to three columns; one and two take 32 rows).
template <int kRows, int kWide, bool kFma>
inline __attribute__((always_inline)) void convolveColumns(const PackedConv& w, const float* const* x,
                                                           const int* first_tap, int n, float* Y) {
  static_assert(kWide >= 1 && kWide <= 4, "the remainder switch handles up to 3 columns");
  const int taps = w.taps;
  auto at = [&](int c) { return x + static_cast<long>(c) * taps; };
  auto out = [&](int c) { return Y + static_cast<long>(c) * w.rows; };
  int c = 0;
  // A block starts at its last column's first tap (the smallest; the others see zeros there).
  for (; c + kWide <= n; c += kWide) convolveBlock<kRows, kWide, kFma>(w, at(c), first_tap[c + kWide - 1], out(c));
  switch (n - c) {
    case 3: convolveBlock<kRows, 3, kFma>(w, at(c), first_tap[c + 2], out(c)); break;
    case 2: convolveBlock<kRowBlock, 2, kFma>(w, at(c), first_tap[c + 1], out(c)); break;
    case 1: convolveBlock<kRowBlock, 1, kFma>(w, at(c), first_tap[c], out(c)); break;
    default: break;
  }
}

#ifdef HDVIO_TCN_AVX2
__attribute__((target("avx2,fma"))) void convolveAvx2(const PackedConv& w, const float* const* x,
                                                      const int* first_tap, int n, float* Y) {
  convolveColumns<32, 3, true>(w, x, first_tap, n, Y);
}

bool hasAvx2Fma() {
  static const bool kHas = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return kHas;
}

// GELU with Eigen's float erf (clamp to [-4, 4], odd/even rational polynomial; the same
// coefficients, so both paths agree to float rounding) in AVX2 + FMA: Eigen itself is
// compiled for plain x86-64 here and would use 4-wide SSE.
__attribute__((target("avx2,fma"))) inline __m256 erfAvx2(__m256 z) {
  z = _mm256_max_ps(_mm256_min_ps(z, _mm256_set1_ps(4.0f)), _mm256_set1_ps(-4.0f));
  const __m256 z2 = _mm256_mul_ps(z, z);
  __m256 p = _mm256_fmadd_ps(z2, _mm256_set1_ps(-2.72614225801306e-10f), _mm256_set1_ps(2.77068142495902e-08f));
  p = _mm256_fmadd_ps(z2, p, _mm256_set1_ps(-2.10102402082508e-06f));
  p = _mm256_fmadd_ps(z2, p, _mm256_set1_ps(-5.69250639462346e-05f));
  p = _mm256_fmadd_ps(z2, p, _mm256_set1_ps(-7.34990630326855e-04f));
  p = _mm256_fmadd_ps(z2, p, _mm256_set1_ps(-2.95459980854025e-03f));
  p = _mm256_fmadd_ps(z2, p, _mm256_set1_ps(-1.60960333262415e-02f));
  p = _mm256_mul_ps(z, p);
  __m256 q = _mm256_fmadd_ps(z2, _mm256_set1_ps(-1.45660718464996e-05f), _mm256_set1_ps(-2.13374055278905e-04f));
  q = _mm256_fmadd_ps(z2, q, _mm256_set1_ps(-1.68282697438203e-03f));
  q = _mm256_fmadd_ps(z2, q, _mm256_set1_ps(-7.37332916720468e-03f));
  q = _mm256_fmadd_ps(z2, q, _mm256_set1_ps(-1.42647390514189e-02f));
  return _mm256_div_ps(p, q);
}

__attribute__((target("avx2,fma"))) inline __m256 geluAvx2(__m256 v) {
  const __m256 e = erfAvx2(_mm256_mul_ps(v, _mm256_set1_ps(0.70710678118654752440f)));
  return _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(0.5f), v), _mm256_add_ps(_mm256_set1_ps(1.0f), e));
}

__attribute__((target("avx2,fma"))) void geluAvx2(float* x, long n) {
  long i = 0;
  // Four independent vectors per iteration: the erf's polynomial chains are latency-bound.
  for (; i + 32 <= n; i += 32) {
    const __m256 a = geluAvx2(_mm256_loadu_ps(x + i)), b = geluAvx2(_mm256_loadu_ps(x + i + 8));
    const __m256 c = geluAvx2(_mm256_loadu_ps(x + i + 16)), d = geluAvx2(_mm256_loadu_ps(x + i + 24));
    _mm256_storeu_ps(x + i, a);
    _mm256_storeu_ps(x + i + 8, b);
    _mm256_storeu_ps(x + i + 16, c);
    _mm256_storeu_ps(x + i + 24, d);
  }
  for (; i + 8 <= n; i += 8) {
    _mm256_storeu_ps(x + i, geluAvx2(_mm256_loadu_ps(x + i)));
  }
  if (i < n) {  // tail through a padded register, same arithmetic
    alignas(32) float buf[8] = {};
    for (long j = i; j < n; ++j) buf[j - i] = x[j];
    _mm256_store_ps(buf, geluAvx2(_mm256_load_ps(buf)));
    for (long j = i; j < n; ++j) x[j] = buf[j - i];
  }
}
#endif

}  // namespace

int paddedRows(int rows) { return (rows + kRowBlock - 1) / kRowBlock * kRowBlock; }

PackedConv packConv(const MatrixXf& weight, const VectorXf& bias, int taps) {
  PackedConv p;
  p.out = static_cast<int>(weight.rows());
  p.rows = paddedRows(p.out);
  p.taps = taps;
  p.in = static_cast<int>(weight.cols()) / taps;
  const long K = weight.cols();
  p.panels.assign(static_cast<std::size_t>(p.rows) * K, 0.0f);
  for (int o = 0; o < p.out; ++o) {
    float* panel = p.panels.data() + static_cast<long>(o / kPanelRows) * K * kPanelRows + o % kPanelRows;
    for (long k = 0; k < K; ++k) panel[k * kPanelRows] = weight(o, k);
  }
  p.bias.assign(static_cast<std::size_t>(p.rows), 0.0f);
  for (int o = 0; o < p.out; ++o) p.bias[o] = bias(o);
  return p;
}

void convolvePortable(const PackedConv& w, const float* const* x, const int* first_tap, int n, float* Y) {
  convolveColumns<8, 4, false>(w, x, first_tap, n, Y);
}

void convolve(const PackedConv& conv, const float* const* inputs, const int* first_tap, int n, float* Y) {
#ifdef HDVIO_TCN_AVX2
  if (hasAvx2Fma()) return convolveAvx2(conv, inputs, first_tap, n, Y);
#endif
  convolvePortable(conv, inputs, first_tap, n, Y);
}

void gelu(float* x, long n) {
#ifdef HDVIO_TCN_AVX2
  if (hasAvx2Fma()) return geluAvx2(x, n);
#endif
  constexpr float kInvSqrt2 = 0.70710678118654752440f;
  Eigen::Map<Eigen::ArrayXf> a(x, n);
  a = 0.5f * a * (1.0f + (a * kInvSqrt2).erf());
}

}  // namespace hdvio::learned::detail
