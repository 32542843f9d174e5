#include "hdvio/learned/torch/tcn_module.h"

#include <algorithm>
#include <stdexcept>

namespace hdvio::learned {
namespace {

MatrixXf toMatrix(const torch::Tensor& t2d) {
  const torch::Tensor c = t2d.detach().to(torch::kCPU, torch::kFloat32).contiguous();
  MatrixXf m(c.size(0), c.size(1));
  const auto a = c.accessor<float, 2>();
  for (long i = 0; i < m.rows(); ++i)
    for (long j = 0; j < m.cols(); ++j) m(i, j) = a[i][j];
  return m;
}

VectorXf toVector(const torch::Tensor& t1d) { return toMatrix(t1d.reshape({-1, 1})); }

torch::Tensor fromMatrix(const MatrixXf& m) {
  torch::Tensor t = torch::empty({m.rows(), m.cols()}, torch::kFloat32);
  auto a = t.accessor<float, 2>();
  for (long i = 0; i < m.rows(); ++i)
    for (long j = 0; j < m.cols(); ++j) a[i][j] = m(i, j);
  return t;
}

}  // namespace

TcnModuleImpl::TcnModuleImpl(const TcnArchitecture& architecture) : arch_(architecture) {
  arch_.validate();
  int width = arch_.input_channels;
  const int per_block = arch_.residual ? 2 : 1;
  for (std::size_t l = 0; l < arch_.layers.size(); ++l) {
    const auto& spec = arch_.layers[l];
    for (int j = 0; j < per_block; ++j) {
      const int in = j == 0 ? width : spec.out_channels;
      convs_.push_back(register_module(
          "conv" + std::to_string(convs_.size()),
          torch::nn::Conv1d(torch::nn::Conv1dOptions(in, spec.out_channels, arch_.kernel_size)
                                .dilation(spec.dilation))));
    }
    if (arch_.residual) {
      skips_.push_back(width == spec.out_channels
                           ? torch::nn::Conv1d(nullptr)
                           : register_module("skip" + std::to_string(l),
                                             torch::nn::Conv1d(torch::nn::Conv1dOptions(
                                                 width, spec.out_channels, 1))));
    }
    width = spec.out_channels;
  }
  head_ = register_module("head", torch::nn::Conv1d(torch::nn::Conv1dOptions(width, arch_.output_channels, 1)));
  if (arch_.variance_head) {
    logvar_ = register_module("logvar", torch::nn::Conv1d(torch::nn::Conv1dOptions(width, arch_.output_channels, 1)));
  }
  mean_ = register_buffer("input_mean", torch::zeros({arch_.input_channels}));
  std_ = register_buffer("input_std", torch::ones({arch_.input_channels}));
  if (arch_.residual) buildLastStepPlan();
}

void TcnModuleImpl::buildLastStepPlan() {
  // Backwards from the window's last step: a convolution outputting steps `out` reads its
  // input at s - (k-1-j) d for each tap j (negative = zero padding).
  const int k = arch_.kernel_size;
  const auto inputSteps = [k](const std::vector<int>& out, int d) {
    std::vector<int> in;
    for (int s : out)
      for (int j = 0; j < k; ++j)
        if (s - (k - 1 - j) * d >= 0) in.push_back(s - (k - 1 - j) * d);
    std::sort(in.begin(), in.end());
    in.erase(std::unique(in.begin(), in.end()), in.end());
    return in;
  };
  const auto positions = [](const std::vector<int>& of, const std::vector<int>& in) {
    std::vector<int64_t> pos;
    for (int s : of) {
      const auto it = std::lower_bound(in.begin(), in.end(), s);
      pos.push_back(s < 0 ? static_cast<int64_t>(in.size()) : static_cast<int64_t>(it - in.begin()));
    }
    return torch::tensor(pos, torch::kInt64);
  };
  const std::size_t blocks = arch_.layers.size();
  std::vector<std::vector<int>> steps(2 * blocks + 1);  // steps[c] = input steps of conv c
  steps[2 * blocks] = {arch_.window - 1};
  for (std::size_t l = blocks; l-- > 0;) {
    const int d = arch_.layers[l].dilation;
    steps[2 * l + 1] = inputSteps(steps[2 * l + 2], d);
    std::vector<int> in = inputSteps(steps[2 * l + 1], d);
    for (int s : steps[2 * l + 2]) in.push_back(s);  // the skip reads the block's output steps
    std::sort(in.begin(), in.end());
    in.erase(std::unique(in.begin(), in.end()), in.end());
    steps[2 * l] = in;
  }
  tap_index_.assign(2 * blocks, {});
  skip_index_.assign(blocks, {});
  for (std::size_t c = 0; c < 2 * blocks; ++c) {
    const int d = arch_.layers[c / 2].dilation;
    for (int j = 0; j < k; ++j) {
      std::vector<int> taps;
      for (int s : steps[c + 1]) taps.push_back(s - (k - 1 - j) * d);
      tap_index_[c].push_back(positions(taps, steps[c]));
    }
  }
  for (std::size_t l = 0; l < blocks; ++l) skip_index_[l] = positions(steps[2 * l + 2], steps[2 * l]);
  input_index_ = torch::tensor(std::vector<int64_t>(steps[0].begin(), steps[0].end()), torch::kInt64);
}

torch::Tensor TcnModuleImpl::forwardLast(const torch::Tensor& x) {
  if (!arch_.residual) throw std::logic_error("forwardLast needs a residual architecture");
  namespace F = torch::nn::functional;
  const int64_t batch = x.size(0);
  // Step-major layout (steps x batch x channels): selecting steps is one index_select and each
  // convolution tap is one (steps * batch) x in by in x out product.
  torch::Tensor h = ((x.index_select(2, input_index_) - mean_.view({1, -1, 1})) / std_.view({1, -1, 1}))
                        .permute({2, 0, 1});
  const auto pointwise = [batch](const torch::Tensor& in, const torch::Tensor& w, const torch::Tensor& b) {
    return F::linear(in.reshape({-1, in.size(2)}), w, b).view({in.size(0), batch, w.size(0)});
  };
  // A convolution at the planned steps: sum over taps j of W_j x[taps_j] + b, with the zero
  // padding as an appended zero step.
  const auto conv = [&](std::size_t c, const torch::Tensor& in) {
    const torch::Tensor padded = torch::cat({in, torch::zeros({1, batch, in.size(2)}, in.options())}, 0);
    const torch::Tensor& w = convs_[c]->weight;  // out x in x k
    torch::Tensor y;
    for (std::size_t j = 0; j < tap_index_[c].size(); ++j) {
      const torch::Tensor tap = padded.index_select(0, tap_index_[c][j]);
      const torch::Tensor wj = w.select(2, static_cast<int64_t>(j));
      y = j == 0 ? pointwise(tap, wj, convs_[c]->bias) : y + pointwise(tap, wj, torch::Tensor());
    }
    return y;
  };
  for (std::size_t l = 0; l < arch_.layers.size(); ++l) {
    const torch::Tensor a = torch::gelu(conv(2 * l, h));
    const torch::Tensor b = torch::gelu(conv(2 * l + 1, a));
    const torch::Tensor in = h.index_select(0, skip_index_[l]);
    h = b + (skips_[l] ? pointwise(in, skips_[l]->weight.squeeze(2), skips_[l]->bias) : in);
    if (arch_.block_relu) h = torch::relu(h);
  }
  torch::Tensor out = pointwise(h, head_->weight.squeeze(2), head_->bias);  // 1 x batch x outputs
  if (arch_.variance_head) out = torch::cat({out, pointwise(h, logvar_->weight.squeeze(2), logvar_->bias)}, 2);
  return out.select(0, 0);
}

void TcnModuleImpl::setNormalization(const torch::Tensor& mean, const torch::Tensor& std) {
  torch::NoGradGuard no_grad;
  mean_.copy_(mean);
  std_.copy_(std);
}

torch::Tensor TcnModuleImpl::forward(const torch::Tensor& x) {
  namespace F = torch::nn::functional;
  torch::Tensor h = (x - mean_.view({1, -1, 1})) / std_.view({1, -1, 1});
  const int per_block = arch_.residual ? 2 : 1;
  for (std::size_t c = 0; c < convs_.size(); ++c) {
    const std::size_t l = c / per_block;
    const int64_t pad = static_cast<int64_t>(arch_.kernel_size - 1) * arch_.layers[l].dilation;
    if (!arch_.residual) {
      h = torch::gelu(convs_[c]->forward(F::pad(h, F::PadFuncOptions({pad, 0}))));
      continue;
    }
    // Residual block: GELU(conv_b(GELU(conv_a(x)))) + skip(x), both convolutions at once;
    // the release variant adds a ReLU after the sum.
    const torch::Tensor a = torch::gelu(convs_[c]->forward(F::pad(h, F::PadFuncOptions({pad, 0}))));
    const torch::Tensor b = torch::gelu(convs_[c + 1]->forward(F::pad(a, F::PadFuncOptions({pad, 0}))));
    h = b + (skips_[l] ? skips_[l]->forward(h) : h);
    if (arch_.block_relu) h = torch::relu(h);
    ++c;
  }
  torch::Tensor out = head_->forward(h);
  if (arch_.variance_head) out = torch::cat({out, logvar_->forward(h)}, 1);
  return out;
}

Tcn exportTcn(TcnModule& module) {
  torch::NoGradGuard no_grad;
  const TcnArchitecture& a = module->architecture();
  TcnWeights w;
  w.input_mean = toVector(module->inputMean());
  w.input_std = toVector(module->inputStd());
  for (auto& conv : module->convs()) {
    // torch weight [out][in][k] -> Eigen (out, k * in): column j * in + i.
    const torch::Tensor wt = conv->weight.detach().permute({0, 2, 1}).reshape({conv->weight.size(0), -1});
    w.conv.push_back({toMatrix(wt), toVector(conv->bias)});
  }
  for (auto& skip : module->skips()) {
    if (!skip) {
      w.skip.push_back({});
    } else {
      w.skip.push_back({toMatrix(skip->weight.squeeze(2)), toVector(skip->bias)});
    }
  }
  w.head_weight = toMatrix(module->head()->weight.squeeze(2));
  w.head_bias = toVector(module->head()->bias);
  if (a.variance_head) {
    w.logvar_weight = toMatrix(module->logvarHead()->weight.squeeze(2));
    w.logvar_bias = toVector(module->logvarHead()->bias);
  }
  return Tcn(a, std::move(w));
}

TcnModule importTcn(const Tcn& tcn) {
  TcnModule module(tcn.architecture());
  torch::NoGradGuard no_grad;
  const TcnWeights& w = tcn.weights();
  module->setNormalization(fromMatrix(w.input_mean).reshape({-1}), fromMatrix(w.input_std).reshape({-1}));
  const int k = tcn.architecture().kernel_size;
  for (std::size_t l = 0; l < module->convs().size(); ++l) {
    auto& conv = module->convs()[l];
    const long out = conv->weight.size(0), in = conv->weight.size(1);
    conv->weight.copy_(fromMatrix(w.conv[l].weight).reshape({out, k, in}).permute({0, 2, 1}));
    conv->bias.copy_(fromMatrix(w.conv[l].bias).reshape({-1}));
  }
  for (std::size_t l = 0; l < module->skips().size(); ++l) {
    auto& skip = module->skips()[l];
    if (!skip) continue;
    skip->weight.copy_(fromMatrix(w.skip[l].weight).unsqueeze(2));
    skip->bias.copy_(fromMatrix(w.skip[l].bias).reshape({-1}));
  }
  module->head()->weight.copy_(fromMatrix(w.head_weight).unsqueeze(2));
  module->head()->bias.copy_(fromMatrix(w.head_bias).reshape({-1}));
  if (tcn.architecture().variance_head) {
    module->logvarHead()->weight.copy_(fromMatrix(w.logvar_weight).unsqueeze(2));
    module->logvarHead()->bias.copy_(fromMatrix(w.logvar_bias).reshape({-1}));
  }
  return module;
}

}  // namespace hdvio::learned
