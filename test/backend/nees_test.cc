// Monte-Carlo consistency: over independent noise realizations of a short simulated flight, the
// normalized estimation error squared (NEES) of the latest pose, computed with the window's own
// marginal covariance, must be chi-square distributed with 6 degrees of freedom.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cstdio>

#include "hdvio/backend/schur_marginalization.h"
#include "hdvio/pipeline/visual_sequence_runner.h"
#include "hdvio/core/config.h"
#include "hdvio/sim/simulator.h"

namespace hdvio {
namespace {
using namespace symbols;

std::string flightWithSeed(int seed) {
  return R"(
name: nees
seed: )" + std::to_string(seed) + R"(
duration: 4.0
trajectory: {type: circle, center: [0.0, 0.0, 1.5], radius: 1.5, max_speed: 2.5, ramp_time: 1.0}
yaw: {mode: oscillate, value_deg: 0.0, amplitude_deg: 20.0, frequency: 0.3}
imu: {rate_hz: 200}
camera: {resolution: [320, 240], rate_hz: 10, intrinsics: [200.0, 200.0, 160.0, 120.0]}
scene: {room_min: [-4.0, -3.0, 0.0], room_max: [4.0, 3.0, 3.0], num_landmarks: 300}
)";
}

// NEES of the latest pose of a backend against the truth, with the window's marginal covariance.
double latestPoseNees(const VioBackend& backend, const Sequence& seq) {
  const SlidingWindowSmoother& sm = backend.smoother();
  const FactorGraph graph = sm.factors();
  const auto keys_set = graph.keys();
  const std::vector<Key> keys(keys_set.begin(), keys_set.end());
  const LinearSystem sys = linearizeDense(graph, sm.estimate(), keys);
  const NavState latest = backend.latestState();
  Key xk;
  for (Key k : keys)
    if (k.letter() == 'x') xk = k;  // keys are sorted: the last pose is the newest
  int offset = 0;
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (keys[i] == xk) offset = sys.offsets[i];
  const Eigen::MatrixXd P = sys.H.ldlt().solve(Eigen::MatrixXd::Identity(sys.H.rows(), sys.H.cols()));
  const Mat6 Pxx = P.block<6, 6>(offset, offset);
  const Vec6 e = latest.T_WB.minus(groundTruthState(seq, latest.t).T_WB);
  return e.dot(Pxx.ldlt().solve(e));
}

TEST(VioConsistency, MonteCarloPoseNeesIsChiSquare) {
  const int runs = 12;
  double sum = 0.0;
  for (int seed = 1; seed <= runs; ++seed) {
    const auto config = sim::loadSimConfig(ConfigReader::fromString(flightWithSeed(seed), "flight"));
    const Sequence seq = sim::Simulator(config).simulate().sequence;
    VioBackendOptions options = defaultVioBackendOptions(VioMethod::kVio);
    options.pixel_sigma = 0.5;
    options.robust_loss = RobustLoss::kNone;
    const CameraModel camera = CameraModel::fromCalibration(*seq.camera);
    VioBackend backend(options, camera, seq.camera->T_BS);
    const auto frames = framesFromTracks(seq, 0.5, static_cast<std::uint32_t>(seed));
    std::size_t imu_next = 0;
    for (std::size_t f = 0; f < frames.size(); ++f) {
      while (imu_next < seq.imu.size() && seq.imu[imu_next].t <= frames[f].t)
        backend.addImu(seq.imu[imu_next++]);
      if (f == 0) {
        backend.initialize(groundTruthState(seq, frames[0].t));
      } else {
        backend.addFrame(frames[f]);
      }
    }
    const double nees = latestPoseNees(backend, seq);
    std::printf("seed %d: NEES %.2f\n", seed, nees);
    sum += nees;
  }
  const double mean = sum / runs;
  std::printf("mean pose NEES over %d runs: %.2f (6 expected)\n", runs, mean);
  // chi2(6 * runs) / runs two-sided 99% bounds for 12 runs (72 dof): [45.0, 105.0] / 12.
  EXPECT_GT(mean, 45.0 / runs);
  EXPECT_LT(mean, 105.0 / runs);
}

}  // namespace
}  // namespace hdvio
