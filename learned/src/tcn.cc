#include "hdvio/learned/tcn.h"

#include <stdexcept>

#include "tcn_kernels.h"
#include "tcn_plan.h"

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

  inference_ = std::make_shared<const detail::TcnInference>(arch_, weights_);
}

std::size_t Tcn::parameterCount() const {
  std::size_t n = 0;
  for (const auto& c : weights_.conv) n += c.weight.size() + c.bias.size();
  for (const auto& c : weights_.skip) n += c.weight.size() + c.bias.size();
  n += weights_.head_weight.size() + weights_.head_bias.size();
  n += weights_.logvar_weight.size() + weights_.logvar_bias.size();
  return n;
}

TcnOutput Tcn::predictWindow(const MatrixXf& window) const {
  TcnWorkspace workspace;
  return predictWindow(window, &workspace);
}

TcnOutput Tcn::predictWindow(const MatrixXf& window, TcnWorkspace* workspace) const {
  if (window.rows() != arch_.input_channels || window.cols() != arch_.window) {
    throw std::invalid_argument("window has shape " + std::to_string(window.rows()) + "x" +
                                std::to_string(window.cols()) + ", expected " +
                                std::to_string(arch_.input_channels) + "x" +
                                std::to_string(arch_.window));
  }
  const auto x = inference_->run(inference_->window, window, workspace);  // the last step only
  TcnOutput out;
  out.force = weights_.head_weight * x.col(0) + weights_.head_bias;
  if (arch_.variance_head) out.log_variance = weights_.logvar_weight * x.col(0) + weights_.logvar_bias;
  return out;
}

MatrixXf Tcn::forwardSequence(const MatrixXf& inputs) const {
  if (inputs.rows() != arch_.input_channels) {
    throw std::invalid_argument("inputs have " + std::to_string(inputs.rows()) +
                                " channels, expected " + std::to_string(arch_.input_channels));
  }
  const int steps = static_cast<int>(inputs.cols());
  std::vector<int> all(steps);
  for (int t = 0; t < steps; ++t) all[t] = t;
  const detail::TcnPlan plan =
      detail::makePlan(arch_, std::vector<std::vector<int>>(arch_.convolutionCount() + 1, all));
  TcnWorkspace workspace;
  const MatrixXf x = inference_->run(plan, inputs, &workspace);
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

void geluInPlace(MatrixXf* x) { detail::gelu(x->data(), x->size()); }

}  // namespace hdvio::learned
