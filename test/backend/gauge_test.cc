// After marginalization, the prior of a visual-inertial window must not carry information
// along the four unobservable directions (global translation and yaw about gravity); so after a
// solve stopped by its iteration budget the window holds its gauge itself, at its oldest state.
#include <gtest/gtest.h>

#include <cmath>

#include "hdvio/backend/gauge_transform.h"
#include "hdvio/backend/sliding_window_smoother.h"
#include "hdvio/backend/vio_backend.h"

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

// The rotation from a to b about world z (the z part of the world-frame rotation vector): the
// yaw a change of gauge holds.
double yawFrom(const Pose& a, const Pose& b) {
  return Eigen::AngleAxisd(b.R() * a.R().transpose()).angle() *
         Eigen::AngleAxisd(b.R() * a.R().transpose()).axis().z();
}

TEST(GaugeTransform, RestoringReturnsPositionAndYawAndKeepsTilt) {
  const Pose reference(Quat(Eigen::AngleAxisd(0.7, Vec3(0.2, -0.3, 1.0).normalized())), Vec3(4, -2, 1.5));
  // The same pose after a tilt change (about world x) and a gauge move (yaw 0.05 rad about z,
  // a translation).
  const Quat yaw(Eigen::AngleAxisd(0.05, Vec3::UnitZ()));
  const Quat tilt(Eigen::AngleAxisd(0.01, Vec3::UnitX()));
  const Pose moved(yaw * tilt * reference.q, yaw * reference.p + Vec3(0.3, -0.1, 0.2));
  const GaugeTransform g = GaugeTransform::restoring(reference, moved);
  const Pose back = g.pose(moved);
  EXPECT_LT((back.p - reference.p).norm(), 1e-12);
  EXPECT_NEAR(yawFrom(reference, back), 0.0, 1e-12);
  EXPECT_NEAR(back.q.angularDistance(reference.q), 0.01, 1e-4);  // the tilt stays
  // A point and a vector of the window move with it.
  Values v;
  v.insertVector(L(1), moved.p + Vec3(1, 2, 3));
  v.insertVector(V(1), Vec3(1, 0, 0));
  v.insertVector(B(1), Eigen::VectorXd::Constant(6, 0.1));
  g.apply(&v);
  EXPECT_LT((v.vec3(L(1)) - (reference.p + g.R * Vec3(1, 2, 3))).norm(), 1e-12);
  EXPECT_NEAR(std::atan2(v.vec3(V(1)).y(), v.vec3(V(1)).x()), -0.05, 1e-3);
  EXPECT_EQ(v.vector(B(1)), Eigen::VectorXd::Constant(6, 0.1));
}

// A change of gauge moves the marginalization prior's linearization point with the window:
// the prior (and every other factor) says what it said.
TEST(GaugeTransform, SmootherChangeKeepsThePriorsError) {
  Values x0;
  x0.insertPose(X(1), Pose(Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ())), Vec3(1, 2, 3)));
  x0.insertVector(V(1), Vec3(2, 0, 0));
  Eigen::MatrixXd J = Eigen::MatrixXd::Identity(9, 9);
  J(0, 1) = 0.5;
  Eigen::VectorXd r0 = Eigen::VectorXd::Constant(9, 0.1);
  SlidingWindowSmoother smoother;
  Values x = x0;
  x.updatePose(X(1), Pose(x0.pose(X(1)).q, Vec3(1.2, 1.9, 3.1)));
  FactorGraph g;
  g.add(std::make_shared<MarginalizationPrior>(std::vector<Key>{X(1), V(1)}, x0, J, r0));
  smoother.update(g, x, {}, /*optimize=*/false);
  const double before = smoother.factor(0)->error(smoother.estimate());
  GaugeTransform gauge;
  gauge.from = Vec3(1, 1, 1);
  gauge.to = Vec3(-3, 5, 0);
  smoother.changeGauge(gauge);
  EXPECT_LT((smoother.estimate().pose(X(1)).p - Vec3(-2.8, 5.9, 2.1)).norm(), 1e-12);
  EXPECT_NEAR(smoother.factor(0)->error(smoother.estimate()), before, 1e-12);
}

// After a solve stopped by its iteration budget the window holds its gauge at its oldest state:
// the oldest state's position and yaw are where they were before (only the start's prior,
// weakened by the drift, holds them, so such a solve can move the whole window nearly freely)
// and the rest of the window still moves relative to it. A converged solve is the optimum of
// the window and its priors and stays as it is.
struct GaugeMoves {
  int stopped = 0, converged = 0;  // solves where the oldest state stayed in the window
  double max_oldest_move_stopped = 0.0, max_oldest_yaw_stopped = 0.0;
  double max_oldest_move_converged = 0.0, max_relative_move = 0.0;
};

GaugeMoves oldestStateMoves(int max_iterations) {
  const auto config = sim::loadSimConfig(ConfigReader::fromString(kFlight, "flight"));
  const Sequence seq = sim::Simulator(config).simulate().sequence;
  const auto frames = framesFromTracks(seq, 1.0, 1);
  VioBackendOptions options = defaultVioBackendOptions(VioMethod::kVio);
  options.max_iterations = max_iterations;
  VioBackend backend(options, CameraModel::fromCalibration(*seq.camera), seq.camera->T_BS);
  std::size_t next_imu = 0;
  GaugeMoves m;
  for (const auto& frame : frames) {
    while (next_imu < seq.imu.size() && seq.imu[next_imu].t <= frame.t) backend.addImu(seq.imu[next_imu++]);
    if (!backend.initialized()) {
      backend.initialize(groundTruthState(seq, frame.t));
      continue;
    }
    const std::vector<VioBackend::WindowPose> before = backend.windowPoses();
    const FrameResult r = backend.addFrame(frame);
    const std::vector<VioBackend::WindowPose> after = backend.windowPoses();
    for (std::size_t i = 1; i < before.size(); ++i)
      for (const VioBackend::WindowPose& a : after)
        if (a.t == before[i].t) m.max_relative_move = std::max(m.max_relative_move, (a.T_WB.p - before[i].T_WB.p).norm());
    if (after.front().t != before.front().t) continue;  // the oldest left after the solve
    const double move = (after.front().T_WB.p - before.front().T_WB.p).norm();
    if (r.solve_converged) {
      ++m.converged;
      m.max_oldest_move_converged = std::max(m.max_oldest_move_converged, move);
    } else {
      ++m.stopped;
      m.max_oldest_move_stopped = std::max(m.max_oldest_move_stopped, move);
      m.max_oldest_yaw_stopped = std::max(m.max_oldest_yaw_stopped,
                                          std::abs(yawFrom(before.front().T_WB, after.front().T_WB)));
    }
  }
  return m;
}

TEST(VioGauge, SolvesStoppedByTheBudgetKeepTheOldestStatesPositionAndYaw) {
  const GaugeMoves m = oldestStateMoves(/*max_iterations=*/1);
  EXPECT_GE(m.stopped, 10);
  EXPECT_LT(m.max_oldest_move_stopped, 1e-9);
  EXPECT_LT(m.max_oldest_yaw_stopped, 1e-9);
  EXPECT_GT(m.max_relative_move, 1e-4);
}

TEST(VioGauge, ConvergedSolvesMoveTheOldestStateFreely) {
  const GaugeMoves m = oldestStateMoves(/*max_iterations=*/50);
  EXPECT_GE(m.converged, 10);
  // The first state, held by the start's prior, moves little, but not zero as a hold would.
  EXPECT_GT(m.max_oldest_move_converged, 1e-8);
}

}  // namespace
}  // namespace hdvio
