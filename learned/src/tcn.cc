#include "hdvio/learned/tcn.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include <unsupported/Eigen/SpecialFunctions>

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#endif

namespace hdvio::learned {
namespace {

void require(bool ok, const std::string& problem) {
  if (!ok) throw std::invalid_argument(problem);
}

bool allFinite(const MatrixXf& m) { return m.size() == 0 || m.allFinite(); }

void checkShape(const MatrixXf& m, long rows, long cols, const std::string& what) {
  require(m.rows() == rows && m.cols() == cols,
          what + " has shape " + std::to_string(m.rows()) + "x" + std::to_string(m.cols()) +
              ", expected " + std::to_string(rows) + "x" + std::to_string(cols));
  require(allFinite(m), what + " holds NaN or inf");
}

// Stacks the taps of a causal dilated convolution for the output steps `out_steps`:
// block j of column c is the input at out_steps[c] - (k-1-j) d, or zero before the start.
// column_of[s] is the column of step s in `input` (-1 if not available; never hit when the
// needed sets are consistent).
MatrixXf stackTaps(const MatrixXf& input, const std::vector<int>& column_of,
                   const std::vector<int>& out_steps, int kernel, int dilation) {
  const long in = input.rows();
  MatrixXf stacked(kernel * in, static_cast<long>(out_steps.size()));
  for (std::size_t c = 0; c < out_steps.size(); ++c) {
    for (int j = 0; j < kernel; ++j) {
      const int s = out_steps[c] - (kernel - 1 - j) * dilation;
      auto block = stacked.block(j * in, static_cast<long>(c), in, 1);
      if (s < 0) {
        block.setZero();
      } else {
        block = input.col(column_of[s]);
      }
    }
  }
  return stacked;
}

// column_of[s] = position of step s in `steps`, -1 for the others.
void mapColumns(const std::vector<int>& steps, std::vector<int>* column_of) {
  std::fill(column_of->begin(), column_of->end(), -1);
  for (std::size_t c = 0; c < steps.size(); ++c) (*column_of)[steps[c]] = static_cast<int>(c);
}

// y = W s + b for n columns s (K floats each, contiguous), W column-major out x K: a
// register-blocked kernel (kRows outputs x kCols columns of accumulators) that GCC
// vectorizes. Requires out % kRows == 0.
// Exactly kCols columns starting at S, all outputs.
template <int kRows, int kCols, bool kFma>
inline __attribute__((always_inline)) void denseColumns(const float* W, const float* b, int out,
                                                        int K, const float* S, float* Y) {
  for (int o0 = 0; o0 < out; o0 += kRows) {
    float acc[kCols][kRows] = {};
    for (int k = 0; k < K; ++k) {
      const float* w = W + static_cast<long>(k) * out + o0;
#pragma GCC unroll 4
      for (int c = 0; c < kCols; ++c) {
        const float x = S[static_cast<long>(c) * K + k];
#pragma GCC unroll 32
        for (int o = 0; o < kRows; ++o) {
          if constexpr (kFma) {
            acc[c][o] = __builtin_fmaf(w[o], x, acc[c][o]);
          } else {
            acc[c][o] += w[o] * x;
          }
        }
      }
    }
    for (int c = 0; c < kCols; ++c) {
      float* y = Y + static_cast<long>(c) * out + o0;
      for (int o = 0; o < kRows; ++o) y[o] = acc[c][o] + b[o0 + o];
    }
  }
}

// Blocks of four columns, then the remainder with a kernel of its exact width (the last
// layers of a window need only one to three columns).
template <int kRows, bool kFma>
inline __attribute__((always_inline)) void denseBody(const float* W, const float* b, int out, int K,
                                                     const float* S, int n, float* Y) {
  int c = 0;
  for (; c + 4 <= n; c += 4) denseColumns<kRows, 4, kFma>(W, b, out, K, S + static_cast<long>(c) * K, Y + static_cast<long>(c) * out);
  const long so = static_cast<long>(c) * K, yo = static_cast<long>(c) * out;
  switch (n - c) {
    case 3: denseColumns<kRows, 3, kFma>(W, b, out, K, S + so, Y + yo); break;
    case 2: denseColumns<kRows, 2, kFma>(W, b, out, K, S + so, Y + yo); break;
    case 1: denseColumns<2 * kRows, 1, kFma>(W, b, out, K, S + so, Y + yo); break;
    default: break;
  }
}

void denseDefault(const float* W, const float* b, int out, int K, const float* S, int n, float* Y) {
  denseBody<8, false>(W, b, out, K, S, n, Y);
}

#if defined(__GNUC__) && defined(__x86_64__)
#define HDVIO_TCN_AVX2 1
// The same kernel compiled for AVX2 + FMA, used when the CPU has them (runtime check), so
// the library itself stays buildable and runnable for plain x86-64.
__attribute__((target("avx2,fma"))) void denseAvx2(const float* W, const float* b, int out, int K,
                                                   const float* S, int n, float* Y) {
  denseBody<16, true>(W, b, out, K, S, n, Y);
}
#endif

#ifdef HDVIO_TCN_AVX2
// AVX-512: 32 outputs (two registers) x kCols columns of accumulators; the same
// multiply-adds in the same order as the AVX2 + FMA kernel, so both give identical floats.
template <int kCols>
__attribute__((target("avx512f"), always_inline)) inline void denseColumns512(
    const float* W, const float* b, int out, int K, const float* S, float* Y) {
  for (int o0 = 0; o0 < out; o0 += 32) {
    __m512 lo[kCols], hi[kCols];
    for (int c = 0; c < kCols; ++c) lo[c] = hi[c] = _mm512_setzero_ps();
    for (int k = 0; k < K; ++k) {
      const float* w = W + static_cast<long>(k) * out + o0;
      const __m512 w_lo = _mm512_loadu_ps(w), w_hi = _mm512_loadu_ps(w + 16);
      for (int c = 0; c < kCols; ++c) {
        const __m512 x = _mm512_set1_ps(S[static_cast<long>(c) * K + k]);
        lo[c] = _mm512_fmadd_ps(w_lo, x, lo[c]);
        hi[c] = _mm512_fmadd_ps(w_hi, x, hi[c]);
      }
    }
    const __m512 b_lo = _mm512_loadu_ps(b + o0), b_hi = _mm512_loadu_ps(b + o0 + 16);
    for (int c = 0; c < kCols; ++c) {
      float* y = Y + static_cast<long>(c) * out + o0;
      _mm512_storeu_ps(y, _mm512_add_ps(lo[c], b_lo));
      _mm512_storeu_ps(y + 16, _mm512_add_ps(hi[c], b_hi));
    }
  }
}

__attribute__((target("avx512f"))) void denseAvx512(const float* W, const float* b, int out, int K,
                                                     const float* S, int n, float* Y) {
  int c = 0;
  for (; c + 8 <= n; c += 8) denseColumns512<8>(W, b, out, K, S + static_cast<long>(c) * K, Y + static_cast<long>(c) * out);
  const long so = static_cast<long>(c) * K, yo = static_cast<long>(c) * out;
  switch (n - c) {
    case 7: denseColumns512<7>(W, b, out, K, S + so, Y + yo); break;
    case 6: denseColumns512<6>(W, b, out, K, S + so, Y + yo); break;
    case 5: denseColumns512<5>(W, b, out, K, S + so, Y + yo); break;
    case 4: denseColumns512<4>(W, b, out, K, S + so, Y + yo); break;
    case 3: denseColumns512<3>(W, b, out, K, S + so, Y + yo); break;
    case 2: denseColumns512<2>(W, b, out, K, S + so, Y + yo); break;
    case 1: denseColumns512<1>(W, b, out, K, S + so, Y + yo); break;
    default: break;
  }
}
#endif

void denseBlocked(const float* W, const float* b, int out, int K, const float* S, int n, float* Y) {
#ifdef HDVIO_TCN_AVX2
  static const bool kHasAvx512 = __builtin_cpu_supports("avx512f");
  if (kHasAvx512) return denseAvx512(W, b, out, K, S, n, Y);
  static const bool kHasAvx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (kHasAvx2) return denseAvx2(W, b, out, K, S, n, Y);
#endif
  denseDefault(W, b, out, K, S, n, Y);
}

// One convolution (or pointwise) layer on stacked taps: W * stacked + b.
MatrixXf affine(const MatrixXf& W, const VectorXf& b, const MatrixXf& stacked) {
  MatrixXf y(W.rows(), stacked.cols());
  if (W.rows() % 32 == 0) {
    denseBlocked(W.data(), b.data(), static_cast<int>(W.rows()), static_cast<int>(W.cols()),
                 stacked.data(), static_cast<int>(stacked.cols()), y.data());
  } else {
    y.noalias() = W * stacked;
    y.colwise() += b;
  }
  return y;
}

}  // namespace

int TcnArchitecture::receptiveField() const {
  int sum = 0;
  for (const auto& l : layers) sum += l.dilation;
  return 1 + (kernel_size - 1) * sum * (residual ? 2 : 1);
}

void TcnArchitecture::validate() const {
  require(input_channels > 0, "input_channels must be positive");
  require(kernel_size >= 1 && kernel_size <= 16, "kernel_size must be in [1, 16]");
  require(window >= 1 && window <= 100000, "window must be in [1, 100000]");
  require(sample_rate_hz > 0.0 && sample_rate_hz < 1e6, "sample_rate_hz must be positive");
  require(!layers.empty(), "at least one convolution layer is needed");
  for (const auto& l : layers) {
    require(l.out_channels > 0 && l.out_channels <= 4096, "layer width must be in [1, 4096]");
    require(l.dilation >= 1 && l.dilation <= 4096, "dilation must be in [1, 4096]");
  }
  require(output_channels == 3, "output_channels must be 3 (a force or a displacement)");
  require(residual || !block_relu, "block_relu needs residual blocks");
  require(window_padding || receptiveField() <= window,
          "receptive field " + std::to_string(receptiveField()) + " exceeds the window " +
              std::to_string(window) + " (allowed only with window_padding)");
}

TcnArchitecture TcnArchitecture::paper(bool variance_head) {
  TcnArchitecture a;
  a.layers = {{64, 1}, {64, 1}, {64, 2}, {64, 2}, {128, 1}, {128, 1}, {128, 1}};
  a.variance_head = variance_head;
  return a;
}

TcnArchitecture TcnArchitecture::imo(int window, double sample_rate_hz) {
  TcnArchitecture a;
  a.residual = true;
  a.window = window;
  a.sample_rate_hz = sample_rate_hz;
  a.layers = {{64, 8}, {64, 8}, {64, 4}, {64, 1}, {128, 1}, {128, 1}, {128, 1}};
  return a;
}

TcnArchitecture TcnArchitecture::imoRelease(int window, double sample_rate_hz) {
  TcnArchitecture a = imo(window, sample_rate_hz);
  a.block_relu = true;
  a.window_padding = true;
  for (std::size_t l = 0; l < a.layers.size(); ++l) a.layers[l].dilation = 1 << l;
  return a;
}

Tcn::Tcn(TcnArchitecture architecture, TcnWeights weights)
    : arch_(std::move(architecture)), weights_(std::move(weights)) {
  arch_.validate();
  const int c_in = arch_.input_channels;
  checkShape(weights_.input_mean, c_in, 1, "input_mean");
  checkShape(weights_.input_std, c_in, 1, "input_std");
  require((weights_.input_std.array() > 0.0f).all(), "input_std must be positive");
  const std::size_t n_conv = static_cast<std::size_t>(arch_.convolutionCount());
  require(weights_.conv.size() == n_conv,
          "expected " + std::to_string(n_conv) + " convolution layers, found " +
              std::to_string(weights_.conv.size()));
  require(weights_.skip.size() == (arch_.residual ? arch_.layers.size() : 0),
          "expected " + std::to_string(arch_.residual ? arch_.layers.size() : 0) +
              " skip connections, found " + std::to_string(weights_.skip.size()));
  int width = c_in;
  const int per_block = arch_.residual ? 2 : 1;
  for (std::size_t l = 0; l < arch_.layers.size(); ++l) {
    const int out = arch_.layers[l].out_channels;
    for (int j = 0; j < per_block; ++j) {
      const std::size_t c = l * per_block + j;
      const std::string name = "conv " + std::to_string(c);
      const int in = j == 0 ? width : out;
      checkShape(weights_.conv[c].weight, out, arch_.kernel_size * in, name + " weight");
      checkShape(weights_.conv[c].bias, out, 1, name + " bias");
    }
    if (arch_.residual) {
      const std::string name = "skip " + std::to_string(l);
      const TcnConvWeights& sk = weights_.skip[l];
      if (width == out) {
        require(sk.weight.size() == 0 && sk.bias.size() == 0,
                name + " must be the identity (block keeps its width)");
      } else {
        checkShape(sk.weight, out, width, name + " weight");
        checkShape(sk.bias, out, 1, name + " bias");
      }
    }
    width = out;
  }
  checkShape(weights_.head_weight, arch_.output_channels, width, "head weight");
  checkShape(weights_.head_bias, arch_.output_channels, 1, "head bias");
  if (arch_.variance_head) {
    checkShape(weights_.logvar_weight, arch_.output_channels, width, "log-variance weight");
    checkShape(weights_.logvar_bias, arch_.output_channels, 1, "log-variance bias");
  } else {
    require(weights_.logvar_weight.size() == 0 && weights_.logvar_bias.size() == 0,
            "log-variance weights given without a variance head");
  }

  // Walk back from the last output to the steps each layer must produce.
  const int k = arch_.kernel_size;
  auto taps = [k](const std::vector<int>& outs, int dilation, std::set<int> steps) {
    for (int t : outs) {
      for (int j = 0; j < k; ++j) {
        const int s = t - (k - 1 - j) * dilation;
        if (s >= 0) steps.insert(s);
      }
    }
    return std::vector<int>(steps.begin(), steps.end());
  };
  const std::size_t n_layers = arch_.layers.size();
  needed_.assign(n_conv + 1, {});
  needed_[n_conv] = {arch_.window - 1};
  for (std::size_t l = n_layers; l-- > 0;) {
    const int d = arch_.layers[l].dilation;
    if (arch_.residual) {
      const std::vector<int>& out = needed_[2 * l + 2];
      needed_[2 * l + 1] = taps(out, d, {});
      needed_[2 * l] = taps(needed_[2 * l + 1], d, std::set<int>(out.begin(), out.end()));
    } else {
      needed_[l] = taps(needed_[l + 1], d, {});
    }
  }
}

std::size_t Tcn::parameterCount() const {
  std::size_t n = 0;
  for (const auto& c : weights_.conv) n += c.weight.size() + c.bias.size();
  for (const auto& c : weights_.skip) n += c.weight.size() + c.bias.size();
  n += weights_.head_weight.size() + weights_.head_bias.size();
  n += weights_.logvar_weight.size() + weights_.logvar_bias.size();
  return n;
}

MatrixXf Tcn::normalize(const MatrixXf& inputs) const {
  return ((inputs.colwise() - weights_.input_mean).array().colwise() /
          weights_.input_std.array())
      .matrix();
}

TcnOutput Tcn::predictWindow(const MatrixXf& window) const {
  if (window.rows() != arch_.input_channels || window.cols() != arch_.window) {
    throw std::invalid_argument("window has shape " + std::to_string(window.rows()) + "x" +
                                std::to_string(window.cols()) + ", expected " +
                                std::to_string(arch_.input_channels) + "x" +
                                std::to_string(arch_.window));
  }
  // Layer input: only the needed columns, with column_of mapping steps to columns.
  std::vector<int> column_of(arch_.window, -1);
  MatrixXf x(arch_.input_channels, static_cast<long>(needed_[0].size()));
  for (std::size_t c = 0; c < needed_[0].size(); ++c) {
    column_of[needed_[0][c]] = static_cast<int>(c);
    x.col(static_cast<long>(c)) = window.col(needed_[0][c]);
  }
  x = run(normalize(x), std::move(column_of), needed_);
  // x holds the single last step.
  TcnOutput out;
  out.force = weights_.head_weight * x.col(0) + weights_.head_bias;
  if (arch_.variance_head) out.log_variance = weights_.logvar_weight * x.col(0) + weights_.logvar_bias;
  return out;
}

MatrixXf Tcn::run(MatrixXf x, std::vector<int> column_of,
                  const std::vector<std::vector<int>>& needed) const {
  return arch_.residual ? runResidual(std::move(x), std::move(column_of), needed)
                        : runPlain(std::move(x), std::move(column_of), needed);
}

MatrixXf Tcn::runPlain(MatrixXf x, std::vector<int> column_of,
                       const std::vector<std::vector<int>>& needed) const {
  for (std::size_t l = 0; l < arch_.layers.size(); ++l) {
    const MatrixXf stacked =
        stackTaps(x, column_of, needed[l + 1], arch_.kernel_size, arch_.layers[l].dilation);
    MatrixXf y = affine(weights_.conv[l].weight, weights_.conv[l].bias, stacked);
    geluInPlace(&y);
    mapColumns(needed[l + 1], &column_of);
    x = std::move(y);
  }
  return x;
}

MatrixXf Tcn::runResidual(MatrixXf x, std::vector<int> column_of,
                          const std::vector<std::vector<int>>& needed) const {
  std::vector<int> mid_column_of(column_of.size(), -1);
  for (std::size_t l = 0; l < arch_.layers.size(); ++l) {
    const int d = arch_.layers[l].dilation, k = arch_.kernel_size;
    const std::vector<int>& mid = needed[2 * l + 1];
    const std::vector<int>& out = needed[2 * l + 2];
    MatrixXf h = affine(weights_.conv[2 * l].weight, weights_.conv[2 * l].bias,
                        stackTaps(x, column_of, mid, k, d));
    geluInPlace(&h);
    mapColumns(mid, &mid_column_of);
    MatrixXf y = affine(weights_.conv[2 * l + 1].weight, weights_.conv[2 * l + 1].bias,
                        stackTaps(h, mid_column_of, out, k, d));
    geluInPlace(&y);
    // Skip: the block input at the output steps (a 1-tap "convolution").
    const MatrixXf x_out = stackTaps(x, column_of, out, 1, 1);
    const TcnConvWeights& skip = weights_.skip[l];
    if (skip.weight.size() == 0) {
      y += x_out;
    } else {
      y += affine(skip.weight, skip.bias, x_out);
    }
    if (arch_.block_relu) y = y.cwiseMax(0.0f);
    mapColumns(out, &column_of);
    x = std::move(y);
  }
  return x;
}

MatrixXf Tcn::forwardSequence(const MatrixXf& inputs) const {
  if (inputs.rows() != arch_.input_channels) {
    throw std::invalid_argument("inputs have " + std::to_string(inputs.rows()) +
                                " channels, expected " + std::to_string(arch_.input_channels));
  }
  const int steps = static_cast<int>(inputs.cols());
  std::vector<int> all(steps), column_of(steps);
  for (int t = 0; t < steps; ++t) all[t] = column_of[t] = t;
  const std::vector<std::vector<int>> needed(needed_.size(), all);
  const MatrixXf x = run(normalize(inputs), std::move(column_of), needed);
  const long rows = arch_.output_channels * (arch_.variance_head ? 2 : 1);
  MatrixXf out(rows, steps);
  out.topRows(arch_.output_channels) =
      (weights_.head_weight * x).colwise() + weights_.head_bias;
  if (arch_.variance_head) {
    out.bottomRows(arch_.output_channels) =
        (weights_.logvar_weight * x).colwise() + weights_.logvar_bias;
  }
  return out;
}

#ifdef HDVIO_TCN_AVX2
namespace {

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

}  // namespace
#endif

void geluInPlace(MatrixXf* x) {
#ifdef HDVIO_TCN_AVX2
  static const bool kHasAvx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (kHasAvx2) return geluAvx2(x->data(), x->size());
#endif
  constexpr float kInvSqrt2 = 0.70710678118654752440f;
  auto a = x->array();
  a = 0.5f * a * (1.0f + (a * kInvSqrt2).erf());
}

}  // namespace hdvio::learned
