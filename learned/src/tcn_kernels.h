#pragma once
// Inference kernels of the Eigen TCN (tcn.cc), internal to hdvio_learned. A convolution is
// evaluated only at the output steps a window needs, as one register-blocked product per
// layer that reads each tap's input column in place (no stacked copy) and starts at the
// first tap outside the causal zero padding. Weights are packed at load time into panels of
// 16 rows, zero-padded to a multiple of kRowBlock rows, so the kernels stream them in order.
// Each output is the same chain of float multiply-adds over (tap, input channel) in that
// order, whatever the blocking, so skipping the leading zero taps changes no bit.
#include <vector>

#include "hdvio/learned/tcn.h"

namespace hdvio::learned::detail {

constexpr int kPanelRows = 16;
constexpr int kRowBlock = 32;  // the largest row block of a kernel; padded rows are zero

int paddedRows(int rows);

struct PackedConv {
  int out = 0;     // real output channels
  int rows = 0;    // paddedRows(out): rows of the panels and of the output buffer
  int in = 0;      // input channels per tap
  int taps = 0;    // kernel size (1 for a skip projection)
  // Panel p (rows 16p .. 16p + 15) holds W(16p + r, j * in + i) at p * taps * in * 16 +
  // (j * in + i) * 16 + r; rows >= out are zero.
  std::vector<float> panels;
  std::vector<float> bias;  // rows entries, zero beyond out
};

// weight: out x (taps * in), column block j = tap j (TcnConvWeights' layout).
PackedConv packConv(const MatrixXf& weight, const VectorXf& bias, int taps);

// Y (conv.rows x n, column-major, leading dimension conv.rows) = b + sum_{j, i} W_j(:, i)
// x_{c, j}(i) for each output column c < n, where x_{c, j} = inputs[c * taps + j] (in floats).
// first_tap[c]: the first tap of column c that is not padding (non-increasing in c); the taps
// before it are not read, except where a block of columns mixes first taps: those inputs must
// point at zeros.
void convolve(const PackedConv& conv, const float* const* inputs, const int* first_tap, int n,
              float* Y);
// The plain x86-64 kernel that convolve uses on CPUs without AVX2 + FMA (exposed for tests:
// the same products without fused multiply-adds).
void convolvePortable(const PackedConv& conv, const float* const* inputs, const int* first_tap, int n,
                      float* Y);

// Exact GELU x Phi(x) (Eigen's float erf), in place on n floats.
void gelu(float* x, long n);

}  // namespace hdvio::learned::detail
