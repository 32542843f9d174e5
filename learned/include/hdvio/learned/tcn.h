#pragma once
// Temporal convolutional network (HDVIO Sec. III-D) evaluated with Eigen, no libtorch.
//
// Layout: a stack of causal dilated 1-D convolutions, each followed by GELU (exact erf form,
// torch.nn.GELU's default), then a pointwise linear head to the 3-D residual force and,
// optionally, a second pointwise head to its log-variance. A convolution with kernel size k
// and dilation d computes, for every time step t of its input x (channels x time),
//   y[t] = b + sum_{j=0..k-1} W_j x[t - (k-1-j) d],   x[s < 0] = 0  (left zero padding),
// which is torch.nn.Conv1d applied after F.pad(x, ((k-1) d, 0)). The receptive field is
// 1 + (k-1) * sum(d); the window must be at least that long so that a window's last output
// does not see padding. Computation is in float, as in training.
//
// Residual variant (architecture.residual, IMO/TLIO after Bai et al. 2018): each layer spec is
// a temporal block of two causal convolutions with the block's dilation, each followed by
// GELU, plus a skip connection (identity, or a 1x1 convolution when the width changes):
//   h = GELU(conv_a(x)),  y = GELU(conv_b(h)) + skip(x).
// Its receptive field is 1 + 2 (k-1) sum(d). No dropout / weight norm at inference.
//
// Release variant (architecture.block_relu, the TemporalBlock of Bai et al. as the TLIO and
// IMO releases use it): ReLU after the residual sum, y = ReLU(GELU(conv_b(h)) + skip(x)).
// architecture.window_padding allows a receptive field longer than the window: the window's
// outputs then see the causal zero padding (per convolution input), as they did in training
// (the IMO release: dilations 1 ... 64, receptive field 255 on a 50-sample window).
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace hdvio::learned {

using MatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic>;
using VectorXf = Eigen::Matrix<float, Eigen::Dynamic, 1>;

struct TcnLayerSpec {
  int out_channels = 0;
  int dilation = 1;
};

struct TcnArchitecture {
  int input_channels = 6;   // thrust (3) and bias-corrected gyroscope (3), body frame
  int kernel_size = 2;
  int window = 10;          // samples per input window
  double sample_rate_hz = 100.0;
  std::vector<TcnLayerSpec> layers;
  int output_channels = 3;  // residual force, m/s^2 (mass-normalized), body frame
  bool variance_head = false;
  bool residual = false;    // temporal blocks (see above) instead of single convolutions
  bool block_relu = false;  // residual only: ReLU after the residual sum (release variant)
  bool window_padding = false;  // receptive field may exceed the window (zero padding seen)

  int receptiveField() const;
  // Number of convolutions (2 per layer spec when residual).
  int convolutionCount() const { return static_cast<int>(layers.size()) * (residual ? 2 : 1); }
  // Throws std::invalid_argument naming the first inconsistency.
  void validate() const;
  // The paper's network: 4 layers with 64 filters, 3 with 128, kernel 2, dilations
  // 1,1,2,2 | 1,1,1 -> receptive field 10 = 100 ms at 100 Hz.
  static TcnArchitecture paper(bool variance_head = false);
  // The IMO displacement network: 7 residual blocks [64 x 4, 128 x 3], kernel 2, dilations
  // 8, 8, 4, 1, 1, 1, 1 (receptive field 49 <= window 50, docs/imo_network.md says why this
  // order), 6 inputs, 3 outputs (world-frame displacement).
  static TcnArchitecture imo(int window = 50, double sample_rate_hz = 100.0);
  // The IMO reference release's network: the same widths, dilations 1, 2, ..., 64, block_relu,
  // window_padding (receptive field 255).
  static TcnArchitecture imoRelease(int window = 50, double sample_rate_hz = 100.0);
};

struct TcnConvWeights {
  // out x (kernel_size * in): column block j holds the tap W_j of the formula above (tap k-1
  // multiplies the current sample). torch's weight[o][i][j] is weight(o, j * in + i).
  MatrixXf weight;
  VectorXf bias;
};

struct TcnWeights {
  // Inputs are normalized as (x - input_mean) / input_std before the first layer.
  VectorXf input_mean;
  VectorXf input_std;
  std::vector<TcnConvWeights> conv;  // convolutionCount(); residual: block l = conv[2l], conv[2l+1]
  // Residual only: one per block; empty weight and bias = identity skip (same width).
  std::vector<TcnConvWeights> skip;
  MatrixXf head_weight;  // output_channels x last width
  VectorXf head_bias;
  MatrixXf logvar_weight;  // empty unless variance_head
  VectorXf logvar_bias;
};

struct TcnOutput {
  Eigen::Vector3f force = Eigen::Vector3f::Zero();  // m/s^2, body frame
  Eigen::Vector3f log_variance = Eigen::Vector3f::Zero();  // only with a variance head
};

namespace detail {
struct TcnInference;  // packed weights and the window's evaluation plan (tcn_plan.h)
}

// Scratch memory of Tcn::predictWindow: its buffers grow to the largest call and are reused,
// so that a call allocates nothing once warm. Holds no results; one per thread of calls.
class TcnWorkspace {
 private:
  friend struct detail::TcnInference;
  std::vector<float> input_, block_input_, mid_, block_output_, skip_, zeros_;
  std::vector<const float*> tap_inputs_;
};

class Tcn {
 public:
  // Throws std::invalid_argument if the weights do not fit the architecture or hold NaN/inf.
  Tcn(TcnArchitecture architecture, TcnWeights weights);

  const TcnArchitecture& architecture() const { return arch_; }
  const TcnWeights& weights() const { return weights_; }
  std::size_t parameterCount() const;

  // window: input_channels x architecture().window, oldest sample first, unnormalized.
  // Evaluates only the time steps the last output depends on; `workspace` is scratch.
  TcnOutput predictWindow(const MatrixXf& window, TcnWorkspace* workspace) const;
  // The same with a workspace of its own (allocates per call).
  TcnOutput predictWindow(const MatrixXf& window) const;

  // inputs: input_channels x T. Returns (output_channels [+3]) x T, one causal output per step
  // (steps before the receptive field is filled see zero padding, exactly like torch).
  MatrixXf forwardSequence(const MatrixXf& inputs) const;

 private:
  TcnArchitecture arch_;
  TcnWeights weights_;
  // Immutable after construction, shared by copies.
  std::shared_ptr<const detail::TcnInference> inference_;
};

// Exact GELU, x * Phi(x), applied in place (vectorized erf).
void geluInPlace(MatrixXf* x);

}  // namespace hdvio::learned
