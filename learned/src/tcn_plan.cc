#include "tcn_plan.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <utility>

namespace hdvio::learned::detail {
namespace {

// Tap j of the output at step t reads step t - (taps - 1 - j) * dilation (padding below 0).
ConvColumns convColumns(const std::vector<int>& out_steps, const std::vector<int>& in_steps, int taps,
                        int dilation) {
  std::vector<int> column_of(in_steps.empty() ? 0 : in_steps.back() + 1, -1);
  for (std::size_t c = 0; c < in_steps.size(); ++c) column_of[in_steps[c]] = static_cast<int>(c);
  ConvColumns cols;
  cols.n = static_cast<int>(out_steps.size());
  cols.taps = taps;
  cols.input_column.assign(out_steps.size() * taps, -1);
  cols.first_tap.assign(out_steps.size(), taps);
  for (std::size_t c = 0; c < out_steps.size(); ++c) {
    for (int j = taps - 1; j >= 0; --j) {
      const int s = out_steps[c] - (taps - 1 - j) * dilation;
      if (s < 0) break;  // this tap and the earlier ones are padding
      if (s >= static_cast<int>(column_of.size()) || column_of[s] < 0)
        throw std::logic_error("Tcn plan: step " + std::to_string(s) + " is not evaluated");
      cols.input_column[c * taps + j] = column_of[s];
      cols.first_tap[c] = j;
    }
  }
  return cols;
}

std::size_t ensureSize(std::vector<float>* v, std::size_t n) {
  if (v->size() < n) v->resize(n);
  return n;
}

}  // namespace

TcnPlan makePlan(const TcnArchitecture& a, const std::vector<std::vector<int>>& needed) {
  TcnPlan plan;
  plan.input_steps = needed[0];
  const int k = a.kernel_size;
  for (std::size_t l = 0; l < a.layers.size(); ++l) {
    const int d = a.layers[l].dilation;
    if (a.residual) {
      plan.conv.push_back(convColumns(needed[2 * l + 1], needed[2 * l], k, d));
      plan.conv.push_back(convColumns(needed[2 * l + 2], needed[2 * l + 1], k, d));
      plan.skip.push_back(convColumns(needed[2 * l + 2], needed[2 * l], 1, 1));
    } else {
      plan.conv.push_back(convColumns(needed[l + 1], needed[l], k, d));
    }
  }
  return plan;
}

std::vector<std::vector<int>> windowSteps(const TcnArchitecture& a) {
  const int k = a.kernel_size;
  auto taps = [k](const std::vector<int>& outs, int dilation, std::set<int> steps) {
    for (int t : outs) {
      for (int j = 0; j < k; ++j) {
        const int s = t - (k - 1 - j) * dilation;
        if (s >= 0) steps.insert(s);
      }
    }
    return std::vector<int>(steps.begin(), steps.end());
  };
  const std::size_t n_conv = static_cast<std::size_t>(a.convolutionCount());
  std::vector<std::vector<int>> needed(n_conv + 1);
  needed[n_conv] = {a.window - 1};
  for (std::size_t l = a.layers.size(); l-- > 0;) {
    const int d = a.layers[l].dilation;
    if (a.residual) {
      const std::vector<int>& out = needed[2 * l + 2];
      needed[2 * l + 1] = taps(out, d, {});
      needed[2 * l] = taps(needed[2 * l + 1], d, std::set<int>(out.begin(), out.end()));
    } else {
      needed[l] = taps(needed[l + 1], d, {});
    }
  }
  return needed;
}

TcnInference::TcnInference(const TcnArchitecture& a, const TcnWeights& w)
    : arch(a), input_mean(w.input_mean), input_std(w.input_std) {
  for (const TcnConvWeights& c : w.conv) conv.push_back(packConv(c.weight, c.bias, a.kernel_size));
  for (const TcnConvWeights& s : w.skip) skip.push_back(s.weight.size() == 0 ? PackedConv{} : packConv(s.weight, s.bias, 1));
  window = makePlan(a, windowSteps(a));
}

const float* const* TcnInference::tapInputs(const ConvColumns& columns, const float* input, int ld,
                                            TcnWorkspace* ws) const {
  if (ws->zeros_.size() < static_cast<std::size_t>(ld)) ws->zeros_.assign(ld, 0.0f);
  ws->tap_inputs_.resize(columns.input_column.size());
  for (std::size_t i = 0; i < columns.input_column.size(); ++i) {
    const int col = columns.input_column[i];
    ws->tap_inputs_[i] = col < 0 ? ws->zeros_.data() : input + static_cast<long>(col) * ld;
  }
  return ws->tap_inputs_.data();
}

TcnInference::Activations TcnInference::run(const TcnPlan& plan, const MatrixXf& inputs,
                                            TcnWorkspace* ws) const {
  // Normalized input columns (the same arithmetic as Eigen's (x - mean) / std).
  const int c_in = arch.input_channels;
  const int n0 = static_cast<int>(plan.input_steps.size());
  ensureSize(&ws->input_, static_cast<std::size_t>(c_in) * n0);
  for (int c = 0; c < n0; ++c) {
    const float* src = inputs.data() + static_cast<long>(plan.input_steps[c]) * c_in;
    float* dst = ws->input_.data() + static_cast<long>(c) * c_in;
    for (int i = 0; i < c_in; ++i) dst[i] = (src[i] - input_mean[i]) / input_std[i];
  }
  const float* x = ws->input_.data();
  int ld = c_in, width = c_in;
  std::vector<float>* free_buffer = &ws->block_input_;  // where the next block's input goes
  auto output = [&](std::vector<float>* buffer, const PackedConv& p, int n) {
    ensureSize(buffer, static_cast<std::size_t>(p.rows) * n);
    return buffer->data();
  };
  for (std::size_t l = 0; l < arch.layers.size(); ++l) {
    if (!arch.residual) {
      const ConvColumns& cols = plan.conv[l];
      float* y = output(free_buffer, conv[l], cols.n);
      convolve(conv[l], tapInputs(cols, x, ld, ws), cols.first_tap.data(), cols.n, y);
      gelu(y, static_cast<long>(conv[l].rows) * cols.n);
      x = y;
      ld = conv[l].rows;
      width = conv[l].out;
      free_buffer = free_buffer == &ws->block_input_ ? &ws->block_output_ : &ws->block_input_;
      continue;
    }
    const PackedConv& ca = conv[2 * l];
    const PackedConv& cb = conv[2 * l + 1];
    const ConvColumns& a_cols = plan.conv[2 * l];
    const ConvColumns& b_cols = plan.conv[2 * l + 1];
    float* h = output(&ws->mid_, ca, a_cols.n);
    convolve(ca, tapInputs(a_cols, x, ld, ws), a_cols.first_tap.data(), a_cols.n, h);
    gelu(h, static_cast<long>(ca.rows) * a_cols.n);
    float* y = output(free_buffer, cb, b_cols.n);
    convolve(cb, tapInputs(b_cols, h, ca.rows, ws), b_cols.first_tap.data(), b_cols.n, y);
    const long size = static_cast<long>(cb.rows) * b_cols.n;
    gelu(y, size);
    // Skip: the block input at the output steps, through a 1x1 convolution if the width changes.
    const ConvColumns& s_cols = plan.skip[l];
    if (skip[l].taps == 0) {
      for (int c = 0; c < s_cols.n; ++c) {
        const float* xs = x + static_cast<long>(s_cols.input_column[c]) * ld;
        float* yc = y + static_cast<long>(c) * cb.rows;
        for (int r = 0; r < cb.out; ++r) yc[r] += xs[r];
      }
    } else {
      float* t = output(&ws->skip_, skip[l], s_cols.n);
      convolve(skip[l], tapInputs(s_cols, x, ld, ws), s_cols.first_tap.data(), s_cols.n, t);
      Eigen::Map<Eigen::ArrayXf>(y, size) += Eigen::Map<const Eigen::ArrayXf>(t, size);
    }
    if (arch.block_relu) {
      Eigen::Map<Eigen::ArrayXf> ya(y, size);
      ya = ya.max(0.0f);
    }
    x = y;
    ld = cb.rows;
    width = cb.out;
    free_buffer = free_buffer == &ws->block_input_ ? &ws->block_output_ : &ws->block_input_;
  }
  const int n = plan.conv.back().n;
  return Activations(x, width, n, Eigen::OuterStride<>(ld));
}

}  // namespace hdvio::learned::detail
