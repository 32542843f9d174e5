// hdvio_displacement_bench: time of the IMO displacement network on one thread — the network
// alone per window, and window building (400 Hz IMU + thrust, interpolation, rotation) plus
// the network, as the filter calls them at every 20 Hz update. docs/imo_network.md.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include <gflags/gflags.h>

#include "hdvio/core/error.h"
#include "hdvio/core/thread_clock.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/learned/displacement_model.h"

DEFINE_string(weights, "", "displacement weight file (empty: the IMO architecture with random weights)");
DEFINE_int32(windows, 5000, "windows to time");
DEFINE_double(update_rate_hz, 20.0, "network updates per second of flight (for the real-time factor)");

namespace {

using namespace hdvio;
using namespace hdvio::learned;

double threadCpuMicros() { return 1e6 * hdvio::threadCpuSeconds(); }

DisplacementModel randomModel() {
  std::mt19937 rng(1);
  std::normal_distribution<float> n(0.0f, 1.0f);
  auto random = [&](long r, long c, float s) {
    MatrixXf m(r, c);
    for (long i = 0; i < m.size(); ++i) m.data()[i] = s * n(rng);
    return m;
  };
  const TcnArchitecture a = TcnArchitecture::imo();
  TcnWeights w;
  w.input_mean = VectorXf::Zero(6);
  w.input_std = VectorXf::Ones(6);
  int width = 6;
  for (const auto& l : a.layers) {
    for (int in : {width, l.out_channels}) {
      w.conv.push_back({random(l.out_channels, 2 * in, 1.0f / std::sqrt(2.0f * in)), random(l.out_channels, 1, 0.1f)});
    }
    w.skip.push_back(width == l.out_channels ? TcnConvWeights{}
                                             : TcnConvWeights{random(l.out_channels, width, 0.3f),
                                                              random(l.out_channels, 1, 0.1f)});
    width = l.out_channels;
  }
  w.head_weight = random(3, width, 0.1f);
  w.head_bias = random(3, 1, 0.1f);
  return DisplacementModel(Tcn(a, w), DisplacementInputKind::kThrustGyro, Eigen::Vector3d::Constant(0.05));
}

int run() {
  if (FLAGS_windows < 1) throw InputError("", 0, "--windows must be positive");
  const DisplacementModel model = FLAGS_weights.empty() ? randomModel() : DisplacementModel::load(FLAGS_weights);
  // A synthetic 400 Hz flight long enough for all windows (stride 0.05 s).
  const double seconds = 1.0 + FLAGS_windows * 0.05;
  std::vector<ImuSample> imu;
  std::vector<ThrustSample> thrust;
  for (Timestamp t = 0; toSeconds(t) <= seconds; t += 2500000) {
    const double s = toSeconds(t);
    imu.push_back({t, Vec3(std::sin(s), std::cos(2 * s), 0.3), Vec3(0.5 * std::sin(3 * s), 0.2, 9.81)});
    thrust.push_back({t, Vec3(0.1 * std::sin(s), 0.0, 9.81 + std::cos(s))});
  }
  auto attitude = [](Timestamp t) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * toSeconds(t), Vec3::UnitZ()));
  };
  std::vector<MatrixXf> windows;
  for (int i = 0; i < FLAGS_windows; ++i) {
    windows.push_back(makeDisplacementWindow(model, imu, thrust, fromSeconds(0.6 + 0.05 * i), attitude,
                                             Vec3::Zero(), Vec3::Zero()));
  }
  TcnWorkspace workspace;  // as the filter's network source holds one
  double sink = 0.0;
  for (int i = 0; i < 100; ++i) sink += model.predict(windows[i % windows.size()], &workspace).displacement.sum();  // warm up
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  double c0 = threadCpuMicros();
  for (const MatrixXf& w : windows) sink += model.predict(w, &workspace).displacement.sum();
  const double net_cpu = (threadCpuMicros() - c0) / FLAGS_windows;
  const double net_wall = std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / FLAGS_windows;
  t0 = Clock::now();
  c0 = threadCpuMicros();
  for (int i = 0; i < FLAGS_windows; ++i) {
    const MatrixXf w = makeDisplacementWindow(model, imu, thrust, fromSeconds(0.6 + 0.05 * i), attitude,
                                              Vec3::Zero(), Vec3::Zero());
    sink += model.predict(w, &workspace).displacement.sum();
  }
  const double all_cpu = (threadCpuMicros() - c0) / FLAGS_windows;
  const double all_wall = std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / FLAGS_windows;
  std::printf("parameters             %zu (receptive field %d, window %d)\n", model.tcn().parameterCount(),
              model.tcn().architecture().receptiveField(), model.windowSamples());
  std::printf("network per window     %.2f us CPU, %.2f us wall (%d windows)\n", net_cpu, net_wall, FLAGS_windows);
  std::printf("window build + network %.2f us CPU, %.2f us wall\n", all_cpu, all_wall);
  std::printf("at %.0f Hz updates: %.3f ms CPU per second of flight = %.0fx real time for the network alone\n",
              FLAGS_update_rate_hz, all_cpu * FLAGS_update_rate_hz * 1e-3, 1e6 / (all_cpu * FLAGS_update_rate_hz));
  std::printf("(checksum %g)\n", sink);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_displacement_bench [--weights m.tcn]\n"
      "times the IMO displacement network on one thread\n"
      "example: hdvio_displacement_bench --weights learned/models/imo_blackbird.tcn");
  return runTool(run);
}
