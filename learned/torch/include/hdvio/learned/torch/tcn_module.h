#pragma once
// The TCN of tcn.h as a libtorch module (training only; inference uses the Eigen Tcn).
// Same layout: left zero padding of (k-1) d, Conv1d with dilation d, exact GELU, pointwise
// heads implemented as kernel-1 convolutions. exportTcn/importTcn convert weights exactly.
// Residual architectures: two convolutions per block (convs()[2l], convs()[2l+1]) and a
// kernel-1 skip convolution when the width changes (skips()[l], null for identity);
// architecture.block_relu adds the release's ReLU after the residual sum.
#include <torch/torch.h>

#include "hdvio/learned/tcn.h"

namespace hdvio::learned {

class TcnModuleImpl : public torch::nn::Module {
 public:
  explicit TcnModuleImpl(const TcnArchitecture& architecture);

  // x: batch x input_channels x T (unnormalized) -> batch x (3 [+3 log-variance]) x T.
  torch::Tensor forward(const torch::Tensor& x);
  // Residual architectures only: the last time step of forward(x) (batch x outputs), computed
  // on just the steps it depends on (as Tcn::predictWindow); what training uses, since the
  // loss sees only the window's last output. x: batch x input_channels x architecture().window.
  torch::Tensor forwardLast(const torch::Tensor& x);

  const TcnArchitecture& architecture() const { return arch_; }
  void setNormalization(const torch::Tensor& mean, const torch::Tensor& std);

  std::vector<torch::nn::Conv1d>& convs() { return convs_; }
  std::vector<torch::nn::Conv1d>& skips() { return skips_; }
  torch::nn::Conv1d& head() { return head_; }
  torch::nn::Conv1d& logvarHead() { return logvar_; }
  torch::Tensor& inputMean() { return mean_; }
  torch::Tensor& inputStd() { return std_; }

 private:
  void buildLastStepPlan();

  TcnArchitecture arch_;
  std::vector<torch::nn::Conv1d> convs_;
  std::vector<torch::nn::Conv1d> skips_;
  torch::nn::Conv1d head_{nullptr};
  torch::nn::Conv1d logvar_{nullptr};
  torch::Tensor mean_, std_;  // registered buffers, shape input_channels
  // forwardLast's gather plan per convolution c: the steps it outputs are positions
  // tap_index_[c][j] of its input tensor (tap j; the position one past the input's end stands
  // for the zero padding), skip_index_[l] picks block l's output steps from its input,
  // input_index_ the window steps the first block reads.
  std::vector<std::vector<torch::Tensor>> tap_index_;
  std::vector<torch::Tensor> skip_index_;
  torch::Tensor input_index_;
};
TORCH_MODULE(TcnModule);

// Copies the module's parameters into an Eigen Tcn (float32).
Tcn exportTcn(TcnModule& module);
// Loads an Eigen Tcn's weights into a module of the same architecture.
TcnModule importTcn(const Tcn& tcn);

}  // namespace hdvio::learned
