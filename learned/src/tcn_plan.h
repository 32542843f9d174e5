#pragma once
// How the Eigen TCN (tcn.cc) is evaluated, internal to hdvio_learned: its weights packed for
// the kernels of tcn_kernels.h and, for the output steps a call needs, which input column each
// tap of each convolution reads. Built once per network for predictWindow (the steps the
// window's last output depends on) and per call for forwardSequence (all steps).
#include <vector>

#include <Eigen/Core>

#include "hdvio/learned/tcn.h"
#include "tcn_kernels.h"

namespace hdvio::learned::detail {

// One convolution at the output steps of a call: for output column c and tap j the column of
// the input buffer it reads (-1: causal zero padding), and the first tap that is not padding.
struct ConvColumns {
  int n = 0;
  int taps = 1;
  std::vector<int> input_column;  // n x taps, column c's taps contiguous
  std::vector<int> first_tap;     // n, non-increasing (output steps ascend)
};

// input_steps: the columns of the (unnormalized) input that are read; conv[c] per
// convolution; skip[l] per residual block (1 tap: the block input at the block's output steps).
struct TcnPlan {
  std::vector<int> input_steps;
  std::vector<ConvColumns> conv;
  std::vector<ConvColumns> skip;
};

// needed[c]: the ascending steps of convolution c's input (c < convolutionCount()) and of the
// last output (needed[convolutionCount()]). Residual: needed[2l] = block l's input steps
// (conv_a's taps and the skip), needed[2l + 1] = conv_a's outputs.
TcnPlan makePlan(const TcnArchitecture& a, const std::vector<std::vector<int>>& needed);
// The steps the window's last output depends on, walking back from it.
std::vector<std::vector<int>> windowSteps(const TcnArchitecture& a);

struct TcnInference {
  TcnInference(const TcnArchitecture& a, const TcnWeights& w);

  // The last block's activations (last width rows, one column per output step of the plan),
  // in the workspace; valid until its next use.
  using Activations = Eigen::Map<const MatrixXf, 0, Eigen::OuterStride<>>;
  Activations run(const TcnPlan& plan, const MatrixXf& inputs, TcnWorkspace* ws) const;

  TcnArchitecture arch;
  VectorXf input_mean, input_std;
  std::vector<PackedConv> conv;
  std::vector<PackedConv> skip;  // per residual block; taps == 0: the identity
  TcnPlan window;

 private:
  const float* const* tapInputs(const ConvColumns& columns, const float* input, int ld,
                                TcnWorkspace* ws) const;
};

}  // namespace hdvio::learned::detail
