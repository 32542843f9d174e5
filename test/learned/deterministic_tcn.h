#pragma once
// A TCN whose weights and inputs follow closed formulas, so that the libtorch reference
// outputs in data/tcn_parity_reference.txt can be checked without libtorch.
#include <cmath>
#include <cstdint>

#include "hdvio/learned/tcn.h"

namespace hdvio::learned::testing {

// Integer hash -> uniform in [-1, 1): full-rank, platform-independent pseudo-random values.
inline double hashUniform(std::uint32_t index, std::uint32_t tensor) {
  std::uint32_t x = index * 0x9E3779B1u + tensor * 0x85EBCA6Bu + 0x165667B1u;
  x ^= x >> 15;
  x *= 0x2C1B3C6Du;
  x ^= x >> 12;
  x *= 0x297A2D39u;
  x ^= x >> 15;
  return static_cast<double>(x) / 2147483648.0 - 1.0;
}

// Uniform values with standard deviation `scale`.
inline MatrixXf formulaMatrix(long rows, long cols, int tensor, double scale) {
  MatrixXf m(rows, cols);
  for (long i = 0; i < rows; ++i)
    for (long j = 0; j < cols; ++j)
      m(i, j) = static_cast<float>(scale * std::sqrt(3.0) *
                                   hashUniform(static_cast<std::uint32_t>(i * cols + j), tensor));
  return m;
}

// The paper architecture with a variance head and formula weights scaled by 1/sqrt(fan_in).
inline Tcn deterministicTcn() {
  const TcnArchitecture a = TcnArchitecture::paper(true);
  TcnWeights w;
  w.input_mean = formulaMatrix(6, 1, 0, 0.5);
  w.input_std = (formulaMatrix(6, 1, 1, 0.4).array() + 1.0f).matrix();
  int width = a.input_channels, tensor = 2;
  for (const auto& l : a.layers) {
    const double s = 1.2 / std::sqrt(static_cast<double>(a.kernel_size * width));
    w.conv.push_back({formulaMatrix(l.out_channels, a.kernel_size * width, tensor, s),
                      formulaMatrix(l.out_channels, 1, tensor + 1, 0.1)});
    tensor += 2;
    width = l.out_channels;
  }
  const double s = 1.0 / std::sqrt(static_cast<double>(width));
  w.head_weight = formulaMatrix(3, width, tensor, s);
  w.head_bias = formulaMatrix(3, 1, tensor + 1, 0.1);
  w.logvar_weight = formulaMatrix(3, width, tensor + 2, s);
  w.logvar_bias = formulaMatrix(3, 1, tensor + 3, 0.1);
  return Tcn(a, std::move(w));
}

// The IMO residual architecture (TcnArchitecture::imo(), 7 blocks, skips where the width
// changes) with formula weights; tensors numbered after those of deterministicTcn's range.
inline Tcn deterministicResidualTcn() {
  const TcnArchitecture a = TcnArchitecture::imo();
  TcnWeights w;
  w.input_mean = formulaMatrix(6, 1, 100, 0.5);
  w.input_std = (formulaMatrix(6, 1, 101, 0.4).array() + 1.0f).matrix();
  int width = a.input_channels, tensor = 102;
  auto conv = [&](int out, int in) {
    const double s = 1.0 / std::sqrt(static_cast<double>(a.kernel_size * in));
    TcnConvWeights c{formulaMatrix(out, a.kernel_size * in, tensor, s), formulaMatrix(out, 1, tensor + 1, 0.1)};
    tensor += 2;
    return c;
  };
  for (const auto& l : a.layers) {
    w.conv.push_back(conv(l.out_channels, width));
    w.conv.push_back(conv(l.out_channels, l.out_channels));
    if (width == l.out_channels) {
      w.skip.push_back({});
    } else {
      w.skip.push_back({formulaMatrix(l.out_channels, width, tensor, 1.0 / std::sqrt(width)),
                        formulaMatrix(l.out_channels, 1, tensor + 1, 0.1)});
      tensor += 2;
    }
    width = l.out_channels;
  }
  w.head_weight = formulaMatrix(3, width, tensor, 1.0 / std::sqrt(static_cast<double>(width)));
  w.head_bias = formulaMatrix(3, 1, tensor + 1, 0.1);
  return Tcn(a, std::move(w));
}

// 6 x steps inputs resembling flight: thrust around (0, 0, 9.8) m/s^2, gyro around 1 rad/s.
inline MatrixXf deterministicInputs(int steps) {
  MatrixXf x(6, steps);
  for (int t = 0; t < steps; ++t) {
    for (int c = 0; c < 6; ++c) {
      const double wave = std::sin(0.37 * t + 0.9 * c) + 0.3 * std::cos(1.1 * t - c);
      x(c, t) = static_cast<float>(c < 3 ? (c == 2 ? 9.8 : 0.0) + 2.0 * wave : wave);
    }
  }
  return x;
}

constexpr int kParitySteps = 24;
constexpr int kResidualParitySteps = 64;  // > the IMO window of 50

}  // namespace hdvio::learned::testing
