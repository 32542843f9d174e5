// The visual-inertial backends on simulated flights with ground-truth landmark tracks (no
// frontend): accuracy against the simulator's truth, external-force estimation, and the
// unobservable directions of the marginalization prior.
#include "hdvio/pipeline/visual_sequence_runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "hdvio/core/config.h"
#include "hdvio/sim/simulator.h"

namespace hdvio {
namespace {

constexpr const char* kFlight = R"(
name: backend_test
seed: 3
duration: 8.0
trajectory: {type: circle, center: [0.0, 0.0, 1.5], radius: 1.5, max_speed: 3.0, ramp_time: 2.0,
             height_amplitude: 0.2}
yaw: {mode: oscillate, value_deg: 0.0, amplitude_deg: 20.0, frequency: 0.3}
vehicle: {mass: 0.8, rotor_drag: [0.3, 0.3, 0.05], fuselage_drag: 0.01}
wind: {steady: [1.5, 0.5, 0.0]}
imu: {rate_hz: 200}
camera: {resolution: [320, 240], rate_hz: 10, intrinsics: [200.0, 200.0, 160.0, 120.0],
         distortion_model: radial-tangential,
         distortion_coefficients: [-0.05, 0.01, 0.0002, -0.0001]}
scene: {room_min: [-4.0, -3.0, 0.0], room_max: [4.0, 3.0, 3.0], num_landmarks: 400}
)";

const sim::SimulationResult& flight() {
  static const sim::SimulationResult result = [] {
    const sim::SimConfig config = sim::loadSimConfig(ConfigReader::fromString(kFlight, "flight"));
    return sim::Simulator(config).simulate();
  }();
  return result;
}

struct Errors {
  double position_rmse = 0.0;
  double velocity_rmse = 0.0;
  double yaw_free_rotation_deg = 0.0;  // max attitude error
};

// Position-and-yaw alignment at the first state (the estimator's gauge), then errors.
Errors errorsAgainstTruth(const Sequence& seq, const std::vector<NavState>& states) {
  const NavState gt0 = groundTruthState(seq, states.front().t);
  const auto yawOf = [](const Quat& q) {
    const Vec3 x = q * Vec3::UnitX();
    return std::atan2(x.y(), x.x());
  };
  const Quat dq(Eigen::AngleAxisd(yawOf(gt0.T_WB.q) - yawOf(states.front().T_WB.q), Vec3::UnitZ()));
  Errors e;
  for (const auto& s : states) {
    const NavState gt = groundTruthState(seq, s.t);
    const Vec3 p = dq * (s.T_WB.p - states.front().T_WB.p) + gt0.T_WB.p;
    e.position_rmse += (p - gt.T_WB.p).squaredNorm();
    e.velocity_rmse += (dq * s.v_W - gt.v_W).squaredNorm();
    e.yaw_free_rotation_deg = std::max(
        e.yaw_free_rotation_deg, (dq * s.T_WB.q).angularDistance(gt.T_WB.q) * 180.0 / M_PI);
  }
  e.position_rmse = std::sqrt(e.position_rmse / states.size());
  e.velocity_rmse = std::sqrt(e.velocity_rmse / states.size());
  return e;
}

// The runs below start from the ground-truth state and see the tracks with 0.5 px noise.
VioRunOptions truthStartHalfPixelNoise() {
  VioRunOptions run;
  run.init_from_groundtruth = true;
  run.pixel_noise_sigma = 0.5;
  return run;
}

TEST(VioBackend, TracksSimulatedFlightFromGroundTruthInit) {
  const Sequence& seq = flight().sequence;
  const VioRunOptions run = truthStartHalfPixelNoise();
  const auto out = runVioOnTracks(seq, defaultVioBackendOptions(VioMethod::kVio), run);
  ASSERT_GT(out.states.size(), 70u);
  const Errors e = errorsAgainstTruth(seq, out.states);
  std::printf("vio (gt init): position rmse %.4f m, velocity rmse %.4f m/s, max rot %.3f deg, "
              "%.1f ms/frame\n", e.position_rmse, e.velocity_rmse, e.yaw_free_rotation_deg,
              1e3 * out.backend_time_s / out.states.size());
  EXPECT_LT(e.position_rmse, 0.05);
  EXPECT_LT(e.velocity_rmse, 0.05);
  EXPECT_LT(e.yaw_free_rotation_deg, 1.0);
}

// The landmark budget bounds the window (and so the per-frame cost) without losing the
// trajectory; every processed frame reports its own CPU time.
TEST(VioBackend, LandmarkBudgetBoundsTheWindow) {
  const Sequence& seq = flight().sequence;
  const VioRunOptions run = truthStartHalfPixelNoise();
  VioBackendOptions options = defaultVioBackendOptions(VioMethod::kVio);
  options.max_landmarks = 40;
  const auto out = runVioOnTracks(seq, options, run);
  ASSERT_GT(out.states.size(), 70u);
  int max_in_window = 0;
  for (std::size_t i = 1; i < out.frames.size(); ++i) {
    max_in_window = std::max(max_in_window, out.frames[i].landmarks_in_window);
    EXPECT_GT(out.frames[i].cpu_time_s, 0.0);
    EXPECT_LE(out.frames[i].marginalization_cpu_s, out.frames[i].cpu_time_s);
  }
  EXPECT_LE(max_in_window, 40);
  EXPECT_GE(max_in_window, 30);  // the budget is used, not starved
  const Errors e = errorsAgainstTruth(seq, out.states);
  std::printf("vio, 40 landmarks: position rmse %.4f m\n", e.position_rmse);
  EXPECT_LT(e.position_rmse, 0.08);
}

TEST(VioBackend, StaticInitializationOnHoverStart) {
  const Sequence& seq = flight().sequence;
  VioRunOptions run;
  run.pixel_noise_sigma = 0.5;
  const auto out = runVioOnTracks(seq, defaultVioBackendOptions(VioMethod::kVio), run);
  ASSERT_GT(out.states.size(), 60u);
  const Errors e = errorsAgainstTruth(seq, out.states);
  std::printf("vio (static init): position rmse %.4f m, velocity rmse %.4f m/s\n",
              e.position_rmse, e.velocity_rmse);
  EXPECT_LT(e.position_rmse, 0.1);
  EXPECT_LT(e.velocity_rmse, 0.1);
}

// RMSE of the estimated external force (world) against the simulator's drag + disturbance
// force rotated to the world: with no residual-force model, the dynamics attribute every
// non-thrust force to f_ext.
double forceRmse(const Sequence& seq, const std::vector<NavState>& states) {
  double sum = 0.0;
  int n = 0;
  for (const auto& s : states) {
    auto it = std::lower_bound(seq.forces.begin(), seq.forces.end(), s.t,
                               [](const ForceSample& f, Timestamp t) { return f.t < t; });
    if (it == seq.forces.end() || std::abs(it->t - s.t) > 1000000) continue;
    const NavState gt = groundTruthState(seq, s.t);
    sum += (s.f_ext_W - gt.T_WB.q * (it->external + it->drag)).squaredNorm();
    ++n;
  }
  return std::sqrt(sum / std::max(n, 1));
}

TEST(VioBackend, DynamicsModesEstimateExternalForce) {
  const Sequence& seq = flight().sequence;
  ASSERT_FALSE(seq.forces.empty());
  const VioRunOptions run = truthStartHalfPixelNoise();
  double zero_force_rmse = 0.0;
  {
    std::vector<NavState> zeros = runVioOnTracks(seq, defaultVioBackendOptions(VioMethod::kVio), run).states;
    for (auto& s : zeros) s.f_ext_W.setZero();
    zero_force_rmse = forceRmse(seq, zeros);
  }
  for (VioMethod method : {VioMethod::kVimo, VioMethod::kVid, VioMethod::kHdvio}) {
    const auto out = runVioOnTracks(seq, defaultVioBackendOptions(method), run);
    ASSERT_GT(out.states.size(), 70u);
    const Errors e = errorsAgainstTruth(seq, out.states);
    // Skip the first second while the force estimate converges from its prior.
    std::vector<NavState> settled(out.states.begin() + 10, out.states.end());
    const double f = forceRmse(seq, settled);
    std::printf("%s: position rmse %.4f m, force rmse %.3f m/s^2 (zero estimate: %.3f)\n",
                toString(method).c_str(), e.position_rmse, f, zero_force_rmse);
    EXPECT_LT(e.position_rmse, 0.05) << toString(method);
    EXPECT_LT(f, 0.6 * zero_force_rmse) << toString(method);
  }
}

}  // namespace
}  // namespace hdvio
