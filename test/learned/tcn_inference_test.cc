// The optimized TCN inference (packed panels, taps read in place, padding taps skipped; see
// learned/src/tcn_kernels.h) against a plain double-precision reference written from the
// definition in tcn.h: random weights and inputs, residual and plain stacks, kernel sizes 2
// and 3, widths that are and are not multiples of the kernels' row block, dilations larger
// than the window. Also the two kernels (AVX2 + FMA and portable) on their own.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "hdvio/learned/tcn.h"
#include "tcn_kernels.h"

namespace hdvio::learned {
namespace {

using MatrixXd = Eigen::MatrixXd;

MatrixXf randomMatrix(std::mt19937* rng, long rows, long cols, double scale) {
  std::normal_distribution<float> n(0.0f, static_cast<float>(scale));
  MatrixXf m(rows, cols);
  for (long i = 0; i < m.size(); ++i) m.data()[i] = n(*rng);
  return m;
}

TcnConvWeights randomConv(std::mt19937* rng, int out, int in, int taps) {
  return {randomMatrix(rng, out, taps * in, 1.2 / std::sqrt(double(taps * in))), randomMatrix(rng, out, 1, 0.1)};
}

Tcn randomTcn(const TcnArchitecture& a, unsigned seed) {
  std::mt19937 rng(seed);
  TcnWeights w;
  w.input_mean = randomMatrix(&rng, a.input_channels, 1, 0.5);
  w.input_std = (randomMatrix(&rng, a.input_channels, 1, 0.2).array().abs() + 0.7f).matrix();
  int width = a.input_channels;
  for (const TcnLayerSpec& l : a.layers) {
    w.conv.push_back(randomConv(&rng, l.out_channels, width, a.kernel_size));
    if (a.residual) {
      w.conv.push_back(randomConv(&rng, l.out_channels, l.out_channels, a.kernel_size));
      w.skip.push_back(width == l.out_channels ? TcnConvWeights{} : randomConv(&rng, l.out_channels, width, 1));
    }
    width = l.out_channels;
  }
  w.head_weight = randomMatrix(&rng, a.output_channels, width, 1.0 / std::sqrt(double(width)));
  w.head_bias = randomMatrix(&rng, a.output_channels, 1, 0.1);
  if (a.variance_head) {
    w.logvar_weight = randomMatrix(&rng, a.output_channels, width, 1.0 / std::sqrt(double(width)));
    w.logvar_bias = randomMatrix(&rng, a.output_channels, 1, 0.1);
  }
  return Tcn(a, std::move(w));
}

// y[t] = b + sum_j W_j x[t - (k-1-j) d], x[s < 0] = 0, every step, in double.
MatrixXd convolveAll(const TcnConvWeights& c, const MatrixXd& x, int taps, int dilation) {
  const long in = x.rows(), T = x.cols();
  MatrixXd y(c.weight.rows(), T);
  for (long t = 0; t < T; ++t) {
    y.col(t) = c.bias.cast<double>();
    for (int j = 0; j < taps; ++j) {
      const long s = t - (taps - 1 - j) * static_cast<long>(dilation);
      if (s >= 0) y.col(t) += c.weight.middleCols(j * in, in).cast<double>() * x.col(s);
    }
  }
  return y;
}

MatrixXd gelu(MatrixXd x) {
  return x.unaryExpr([](double v) { return 0.5 * v * (1.0 + std::erf(v / std::sqrt(2.0))); });
}

// The definition of tcn.h: outputs (3 [+ 3]) x T.
MatrixXd referenceSequence(const Tcn& tcn, const MatrixXf& inputs) {
  const TcnArchitecture& a = tcn.architecture();
  const TcnWeights& w = tcn.weights();
  MatrixXd x = ((inputs.cast<double>().colwise() - w.input_mean.cast<double>()).array().colwise() /
                w.input_std.cast<double>().array())
                   .matrix();
  for (std::size_t l = 0; l < a.layers.size(); ++l) {
    const int d = a.layers[l].dilation, k = a.kernel_size;
    if (!a.residual) {
      x = gelu(convolveAll(w.conv[l], x, k, d));
      continue;
    }
    const MatrixXd h = gelu(convolveAll(w.conv[2 * l], x, k, d));
    MatrixXd y = gelu(convolveAll(w.conv[2 * l + 1], h, k, d));
    y += w.skip[l].weight.size() == 0 ? x : convolveAll(w.skip[l], x, 1, 1);
    if (a.block_relu) y = y.cwiseMax(0.0);
    x = y;
  }
  MatrixXd out(a.variance_head ? 6 : 3, x.cols());
  out.topRows(3) = (w.head_weight.cast<double>() * x).colwise() + w.head_bias.cast<double>();
  if (a.variance_head)
    out.bottomRows(3) = (w.logvar_weight.cast<double>() * x).colwise() + w.logvar_bias.cast<double>();
  return out;
}

// predictWindow (one reused workspace, several windows) and forwardSequence against the
// reference; the tolerance is float round-off through the stack, relative to the output size.
void expectMatchesReference(const Tcn& tcn, unsigned seed) {
  const TcnArchitecture& a = tcn.architecture();
  std::mt19937 rng(seed);
  const MatrixXf inputs = randomMatrix(&rng, a.input_channels, a.window + 40, 2.0);
  const MatrixXd reference = referenceSequence(tcn, inputs);
  const double scale = std::max(1.0, reference.cwiseAbs().maxCoeff());
  ASSERT_GT(reference.cwiseAbs().maxCoeff(), 0.1);  // not trivially zero
  const double tol = 2e-5 * scale;

  // A window's last output sees padding at the window start, like the window alone.
  TcnWorkspace workspace;
  for (int start = 0; start <= 40; start += 8) {
    const MatrixXf window = inputs.middleCols(start, a.window);
    const MatrixXd window_ref = referenceSequence(tcn, window);
    const TcnOutput out = tcn.predictWindow(window, &workspace);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(out.force(i), window_ref(i, a.window - 1), tol) << "start " << start;
      if (a.variance_head) {
        EXPECT_NEAR(out.log_variance(i), window_ref(3 + i, a.window - 1), tol);
      }
    }
    const TcnOutput fresh = tcn.predictWindow(window);  // own workspace: the same floats
    EXPECT_EQ(fresh.force, out.force);
  }
  const MatrixXf seq = tcn.forwardSequence(inputs);
  ASSERT_EQ(seq.rows(), reference.rows());
  EXPECT_LT((seq.cast<double>() - reference).cwiseAbs().maxCoeff(), tol);
}

TcnArchitecture residualArchitecture(int window, int kernel, std::vector<TcnLayerSpec> layers, bool relu) {
  TcnArchitecture a;
  a.residual = true;
  a.block_relu = relu;
  a.window_padding = true;
  a.window = window;
  a.kernel_size = kernel;
  a.layers = std::move(layers);
  return a;
}

TEST(TcnInference, ReleaseShapedNetworkMatchesReference) {
  // The IMO release's shape (dilations 1 ... 64 on a 50-sample window), widths 64 / 128.
  expectMatchesReference(randomTcn(TcnArchitecture::imoRelease(), 1), 11);
}

TEST(TcnInference, OddWidthsKernel3AndDilationsBeyondTheWindowMatchReference) {
  // Widths not multiples of 32 (zero-padded panels), projections at every width change,
  // dilations 16 and 40 on a 12-sample window (their earlier taps are all padding).
  expectMatchesReference(
      randomTcn(residualArchitecture(12, 3, {{20, 1}, {20, 4}, {45, 16}, {7, 40}}, true), 2), 12);
  expectMatchesReference(randomTcn(residualArchitecture(9, 2, {{33, 2}, {64, 3}, {64, 1}}, false), 3), 13);
}

TEST(TcnInference, PlainStackWithVarianceHeadMatchesReference) {
  TcnArchitecture a = TcnArchitecture::paper(true);
  a.layers[1].out_channels = 40;
  expectMatchesReference(randomTcn(a, 4), 14);
  a.window_padding = true;
  a.layers[6].dilation = 30;  // beyond the 10-sample window
  expectMatchesReference(randomTcn(a, 5), 15);
}

// The kernels on a convolution with mixed first taps (padding), against a direct double sum.
TEST(TcnInference, KernelsEqualDirectSumWithPaddingTaps) {
  std::mt19937 rng(6);
  for (const auto& [out, in, taps] : {std::tuple{64, 24, 2}, {40, 7, 3}, {128, 128, 2}}) {
    const TcnConvWeights c = randomConv(&rng, out, in, taps);
    const detail::PackedConv packed = detail::packConv(c.weight, c.bias, taps);
    const int n = 11;
    const MatrixXf x = randomMatrix(&rng, in, n * taps, 1.0);
    std::vector<float> zeros(in, 0.0f);
    std::vector<const float*> inputs(n * taps);
    std::vector<int> first_tap(n);
    for (int col = 0; col < n; ++col) {
      first_tap[col] = std::max(0, taps - 1 - col / 2);  // non-increasing, several padded columns
      for (int j = 0; j < taps; ++j)
        inputs[col * taps + j] = j < first_tap[col] ? zeros.data() : x.col(col * taps + j).data();
    }
    std::vector<float> fast(packed.rows * n, NAN), portable(packed.rows * n, NAN);
    detail::convolve(packed, inputs.data(), first_tap.data(), n, fast.data());
    detail::convolvePortable(packed, inputs.data(), first_tap.data(), n, portable.data());
    for (int col = 0; col < n; ++col) {
      for (int o = 0; o < out; ++o) {
        double sum = c.bias(o);
        for (int j = first_tap[col]; j < taps; ++j)
          for (int i = 0; i < in; ++i) sum += double(c.weight(o, j * in + i)) * x(i, col * taps + j);
        const long at = static_cast<long>(col) * packed.rows + o;
        EXPECT_NEAR(fast[at], sum, 1e-5 * (1.0 + std::abs(sum))) << out << " " << col << " " << o;
        EXPECT_NEAR(portable[at], sum, 1e-5 * (1.0 + std::abs(sum))) << out << " " << col << " " << o;
      }
    }
  }
}

}  // namespace
}  // namespace hdvio::learned
