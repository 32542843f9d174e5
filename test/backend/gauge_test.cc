// After marginalization, the prior of a visual-inertial window must not carry information
// along the four unobservable directions (global translation and yaw about gravity).
#include <gtest/gtest.h>

#include "hdvio/backend/schur_marginalization.h"
#include "hdvio/pipeline/visual_sequence_runner.h"
#include "hdvio/core/config.h"
#include "hdvio/factors/dynamics_factors.h"
#include "hdvio/factors/imu_factor.h"
#include "hdvio/factors/reprojection_factor.h"
#include "hdvio/sim/simulator.h"

namespace hdvio {
namespace {
using namespace symbols;

constexpr const char* kFlight = R"(
name: gauge_test
seed: 5
duration: 2.0
trajectory: {type: circle, center: [0.0, 0.0, 1.5], radius: 1.5, max_speed: 3.0, ramp_time: 0.5}
yaw: {mode: oscillate, value_deg: 0.0, amplitude_deg: 20.0, frequency: 0.3}
wind: {steady: [1.0, 0.5, 0.0]}
imu: {rate_hz: 200}
camera: {resolution: [320, 240], rate_hz: 10, intrinsics: [200.0, 200.0, 160.0, 120.0]}
scene: {room_min: [-4.0, -3.0, 0.0], room_max: [4.0, 3.0, 3.0], num_landmarks: 200}
)";

// Tangent-space directions of a global translation (3) and a yaw rotation about world z (1).
Eigen::MatrixXd gaugeDirections(const Values& v, const std::vector<Key>& keys) {
  int n = 0;
  for (Key k : keys) n += v.tangentDim(k);
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(n, 4);
  const Vec3 ez = Vec3::UnitZ();
  int row = 0;
  for (Key k : keys) {
    switch (k.letter()) {
      case 'x': {
        const Pose T = v.pose(k);
        N.block<3, 3>(row, 0).setIdentity();
        N.block<3, 1>(row, 3) = ez.cross(T.p);
        N.block<3, 1>(row + 3, 3) = T.R().transpose() * ez;
        break;
      }
      case 'l':
        N.block<3, 3>(row, 0).setIdentity();
        N.block<3, 1>(row, 3) = ez.cross(v.vec3(k));
        break;
      case 'v':
      case 'f':
        N.block<3, 1>(row, 3) = ez.cross(v.vec3(k));
        break;
      default:  // biases live in the body frame: unchanged
        break;
    }
    row += v.tangentDim(k);
  }
  return N;
}

TEST(VioGauge, MarginalizationKeepsTranslationAndYawUnobservable) {
  const auto config = sim::loadSimConfig(ConfigReader::fromString(kFlight, "flight"));
  const Sequence seq = sim::Simulator(config).simulate().sequence;
  const auto frames = framesFromTracks(seq, 0.0, 1);
  const CameraModel camera = CameraModel::fromCalibration(*seq.camera);
  const ImuNoiseParams imu;
  ThrustNoiseParams thrust;
  DynamicsFactorParams dyn;  // HdvioDynamicsFactor: touches F_i and F_j

  FactorGraph graph;
  Values values;
  std::map<int, int> seen;
  const int n = 5;
  for (int k = 0; k < n; ++k) {
    const Timestamp t = frames[5 + k].t;
    const NavState s = groundTruthState(seq, t);
    values.insertPose(X(k), s.T_WB);
    values.insertVector(V(k), s.v_W);
    values.insertVector(B(k), s.bias);
    values.insertVector(F(k), Vec3(0.4, -0.2, 0.1));
    if (k > 0) {
      const Timestamp t0 = frames[5 + k - 1].t;
      const NavState s0 = groundTruthState(seq, t0);
      graph.add(std::make_shared<ImuFactor>(
          X(k - 1), V(k - 1), B(k - 1), X(k), V(k), B(k),
          std::make_shared<PreintegratedImu>(PreintegratedImu::integrate(seq.imu, t0, t, s0.bias, imu))));
      graph.add(std::make_shared<HdvioDynamicsFactor>(
          X(k - 1), V(k - 1), F(k - 1), X(k), V(k), F(k), B(k - 1),
          std::make_shared<PreintegratedThrust>(
              PreintegratedThrust::integrate(seq.imu, seq.thrust, t0, t, s0.bias, thrust)),
          dyn));
    }
    for (const auto& f : frames[5 + k].features) seen[f.landmark_id]++;
  }
  for (int k = 0; k < n; ++k) {
    for (const auto& f : frames[5 + k].features) {
      if (seen[f.landmark_id] < 3) continue;
      if (!values.exists(L(f.landmark_id))) values.insertVector(L(f.landmark_id), seq.landmarks.at(f.landmark_id));
      graph.add(std::make_shared<ReprojectionFactor>(X(k), L(f.landmark_id), f.uv, camera,
                                                     seq.camera->T_BS, pixelNoise(1.0)));
    }
  }
  ASSERT_GT(graph.size(), 50u);

  // The whole window has exactly the 4-dimensional gauge null space...
  const auto keys_set = graph.keys();
  const std::vector<Key> keys(keys_set.begin(), keys_set.end());
  const LinearSystem full = linearizeDense(graph, values, keys);
  const Eigen::MatrixXd Nfull = gaugeDirections(values, keys);
  EXPECT_LT((full.H * Nfull).norm(), 1e-6 * full.H.norm());

  // ...and so has the prior left by marginalizing the oldest state and its landmarks.
  std::set<Key> leaving{X(0), V(0), B(0), F(0)};
  for (const auto& f : frames[5].features)
    if (values.exists(L(f.landmark_id))) leaving.insert(L(f.landmark_id));
  const auto prior = marginalizeBySchurComplement(graph, values, leaving);
  ASSERT_TRUE(prior);
  const Eigen::MatrixXd Hp = prior->jacobian().transpose() * prior->jacobian();
  const Eigen::MatrixXd N = gaugeDirections(values, prior->keys());
  const double leak = (Hp * N).norm() / Hp.norm();
  std::printf("prior over %zu keys, rank %ld, gauge leak %.2e\n", prior->keys().size(),
              prior->jacobian().rows(), leak);
  EXPECT_LT(leak, 1e-6);
  // A non-gauge direction (a translation of one pose only) is observable.
  Eigen::VectorXd one = Eigen::VectorXd::Zero(Hp.rows());
  one.head<3>() = Vec3::UnitX();
  EXPECT_GT(one.dot(Hp * one), 1.0);
}

}  // namespace
}  // namespace hdvio
