// hdvio_tcn_bench: time of one residual-force window (Eigen inference, one thread; the
// estimator evaluates one per IMU sample, so it should stay within ~20 us), and of streaming
// inference over a whole flight per sample.
#include <chrono>
#include <cstdio>
#include <random>

#include <gflags/gflags.h>

#include "hdvio/core/error.h"
#include "hdvio/core/thread_clock.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/learned/tcn_weight_file.h"

DEFINE_string(weights, "", "TCN weight file (empty: the paper architecture with random weights)");
DEFINE_int32(windows, 20000, "windows to time");

namespace {
double threadCpuMicros() { return 1e6 * hdvio::threadCpuSeconds(); }
}  // namespace

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_tcn_bench [--weights m.tcn] [--windows N]\n"
      "times residual-force TCN inference (one window, and streaming over a flight)\n"
      "example: hdvio_tcn_bench --windows 20000");
  using namespace hdvio::learned;
  using Clock = std::chrono::steady_clock;
  return hdvio::runTool([] {
    if (FLAGS_windows < 1) throw hdvio::InputError("", 0, "--windows must be positive");
    std::mt19937 rng(1);
    std::normal_distribution<float> n(0.0f, 1.0f);
    auto randomMatrix = [&](long r, long c, float s) {
      MatrixXf m(r, c);
      for (long i = 0; i < m.size(); ++i) m.data()[i] = s * n(rng);
      return m;
    };
    Tcn tcn = [&] {
      if (!FLAGS_weights.empty()) return loadTcnWeights(FLAGS_weights);
      const TcnArchitecture a = TcnArchitecture::paper();
      TcnWeights w;
      w.input_mean = VectorXf::Zero(6);
      w.input_std = VectorXf::Ones(6);
      int width = 6;
      for (const auto& l : a.layers) {
        w.conv.push_back({randomMatrix(l.out_channels, 2 * width, 1.0f / std::sqrt(2.0f * width)),
                          randomMatrix(l.out_channels, 1, 0.1f)});
        width = l.out_channels;
      }
      w.head_weight = randomMatrix(3, width, 0.1f);
      w.head_bias = randomMatrix(3, 1, 0.1f);
      return Tcn(a, w);
    }();
    const int W = tcn.architecture().window;
    const int steps = FLAGS_windows + W - 1;
    const MatrixXf x = randomMatrix(6, steps, 1.0f);
    float sink = 0.0f;
    for (int i = 0; i < 200; ++i) sink += tcn.predictWindow(x.middleCols(i % 100, W)).force.sum();  // warm up
    const auto t0 = Clock::now();
    const double c0 = threadCpuMicros();
    for (int i = 0; i < FLAGS_windows; ++i) sink += tcn.predictWindow(x.middleCols(i, W)).force.sum();
    const double window_cpu = (threadCpuMicros() - c0) / FLAGS_windows;
    const double window_us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / FLAGS_windows;
    const auto t1 = Clock::now();
    const double c1 = threadCpuMicros();
    const MatrixXf seq = tcn.forwardSequence(x);
    const double seq_cpu = (threadCpuMicros() - c1) / steps;
    const double seq_us = std::chrono::duration<double, std::micro>(Clock::now() - t1).count() / steps;
    sink += seq.sum();
    std::printf("parameters            %zu\n", tcn.parameterCount());
    std::printf("window (%d samples)   %.2f us CPU, %.2f us wall per window (%d windows)\n", W, window_cpu,
                window_us, FLAGS_windows);
    std::printf("sequence forward      %.2f us CPU, %.2f us wall per output sample (%d samples)\n", seq_cpu,
                seq_us, steps);
    std::printf("(checksum %g)\n", static_cast<double>(sink));
    return 0;
  });
}
