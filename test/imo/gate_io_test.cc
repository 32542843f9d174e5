// gate_io end to end on the tiny simulated race (config/sim/ci_race_tiny.yaml): the simulator's
// gate-corner detections agree with the camera model, the EKF with gate updates tracks the
// ground truth and recovers from a wrong initial state that IMU dead reckoning never corrects,
// and the hdvio_run pipeline rejects bad configs and sequences without gate files. The runs go
// through the pipeline's InertialEstimator (the ImoStepper with the gate-corner updater).
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>

#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/pipeline/inertial_sequence_runner.h"
#include "hdvio/sim/gate_detections.h"
#include "hdvio/sim/simulator.h"

namespace hdvio::imo {
namespace {

struct Race {
  sim::SimConfig config;
  std::unique_ptr<sim::Simulator> simulator;
  sim::SimulationResult result;
};

// The tiny race without landmarks (not needed here), simulated once for all tests.
const Race& tinyRace() {
  static const Race race = [] {
    Race r;
    r.config = sim::loadSimConfig(
        ConfigReader::fromFile(std::string(HDVIO_SOURCE_DIR) + "/config/sim/ci_race_tiny.yaml"));
    r.config.scene.num_landmarks = 0;
    r.simulator = std::make_unique<sim::Simulator>(r.config);
    r.result = r.simulator->simulate();
    return r;
  }();
  return race;
}

InertialEstimatorOptions raceOptions() {
  // As config/experiments/gate_io.yaml, with the IMU densities of ci_race_tiny (EuRoC).
  const Sequence& seq = tinyRace().result.sequence;
  InertialEstimatorOptions o;
  o.displacement = DisplacementUse::kNone;
  o.gate = GateCornerUpdates{GateCornerOptions{}, CameraModel::fromCalibration(*seq.camera), seq.camera->T_BS};
  ImoFilterOptions& f = o.run.filter;
  f.gyro_noise_density = 1.6968e-4;
  f.accel_noise_density = 2.0e-3;
  f.gyro_random_walk = 1.9393e-5;
  f.accel_random_walk = 3.0e-3;
  f.init_attitude_sigma = f.init_yaw_sigma = 1.0 * M_PI / 180.0;
  f.init_velocity_sigma = 0.1;
  f.init_position_sigma = 0.1;
  f.init_gyro_bias_sigma = 1e-3;
  f.init_accel_bias_sigma = 0.05;
  o.gate->options.pixel_sigma = 1.0;
  o.gate->options.gate_probability = 0.999;
  return o;
}

NavState truthAt(const Sequence& seq, std::size_t k) {
  NavState s;
  s.t = seq.groundtruth[k].t;
  s.T_WB = seq.groundtruth[k].T_WB;
  s.v_W = seq.groundtruth[k].v_W;
  return s;
}

// Position RMSE (m) against the truth at the same IMU samples, for samples after t_from_s.
double positionRmse(const Sequence& seq, const std::vector<NavState>& states, double t_from_s) {
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < states.size(); ++k) {
    EXPECT_EQ(states[k].t, seq.groundtruth[k].t);
    if (secondsBetween(seq.groundtruth.front().t, states[k].t) < t_from_s) continue;
    sum += (states[k].T_WB.p - seq.groundtruth[k].T_WB.p).squaredNorm();
    ++n;
  }
  return std::sqrt(sum / std::max(1, n));
}

// The race's IMU from init (its first sample) and the frames through an InertialEstimator.
ImoRunOutput runRace(const InertialEstimatorOptions& options, const NavState& init,
                       const std::vector<GateFrame>& frames, const DisplacementSource& source = {}) {
  const Sequence& seq = tinyRace().result.sequence;
  DisplacementSourceFactory factory;
  if (source) factory = [source](const InertialBuffers&) { return source; };
  return runInertialOnSequence(seq, {}, frames, seq.imu, init, options, factory);
}

ImoRunOutput runOnRace(const InertialEstimatorOptions& options, const NavState& init, bool with_gates) {
  const Race& race = tinyRace();
  return runRace(options, init, with_gates ? hdvio::gateFrames(race.result.gates) : std::vector<GateFrame>{});
}

TEST(GateIoSim, DetectionsAreNoisyProjectionsOfVisibleMapCorners) {
  const Race& race = tinyRace();
  const io::GateData& g = race.result.gates;
  ASSERT_EQ(g.corners.size(), 16u);  // 4 gates x 4 corners
  ASSERT_GT(g.detections.size(), 80u);
  for (int gate = 0; gate < 4; ++gate) {  // inner opening, gate_inner_size = 1.2 m
    EXPECT_NEAR((g.corners.at({gate, 0}) - g.corners.at({gate, 1})).norm(), 1.2, 1e-9);
    EXPECT_NEAR((g.corners.at({gate, 1}) - g.corners.at({gate, 2})).norm(), 1.2, 1e-9);
    EXPECT_GT(g.corners.at({gate, 0}).z(), g.corners.at({gate, 3}).z());  // 0 is a top corner
  }
  // Each detection minus the projection through the true body pose and the mount is the pixel
  // noise: zero mean, configured spread (1 px).
  const Sequence& seq = race.result.sequence;
  const CameraModel camera = CameraModel::fromCalibration(*seq.camera);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (const io::GateCornerDetection& d : g.detections) {
    const auto it = std::lower_bound(seq.groundtruth.begin(), seq.groundtruth.end(), d.t,
                                     [](const GroundTruthState& s, Timestamp t) { return s.t < t; });
    ASSERT_EQ(it->t, d.t);  // camera times are IMU times
    Vec2 uv;
    ASSERT_TRUE(projectGateCorner(camera, seq.camera->T_BS, it->T_WB.R(), it->T_WB.p,
                                  g.corners.at({d.gate_id, d.corner_id}), &uv));
    const Vec2 e = Vec2(d.u, d.v) - uv;
    EXPECT_LT(e.norm(), 6.0);
    sum += e.sum();
    sum2 += e.squaredNorm();
    n += 2;
  }
  EXPECT_NEAR(sum / n, 0.0, 0.2);
  EXPECT_NEAR(std::sqrt(sum2 / n), race.config.gate_detection.pixel_noise, 0.15);
  // Dropout removes about that share of the detections; same seed, same output.
  std::vector<std::pair<Timestamp, Pose>> frames;
  for (const io::GateCornerDetection& d : g.detections)
    if (frames.empty() || frames.back().first != d.t)
      frames.emplace_back(d.t, race.simulator->cameraPose(secondsBetween(race.config.start_time_ns, d.t)));
  sim::GateDetectionConfig half = race.config.gate_detection;
  half.dropout = 0.5;
  const io::GateData a = sim::detectGateCorners(*race.simulator->scene(), *race.simulator->camera(), half, frames, 5);
  const io::GateData b = sim::detectGateCorners(*race.simulator->scene(), *race.simulator->camera(), half, frames, 5);
  EXPECT_NEAR(static_cast<double>(a.detections.size()) / g.detections.size(), 0.5, 0.12);
  ASSERT_EQ(a.detections.size(), b.detections.size());
  EXPECT_EQ(a.detections.back().u, b.detections.back().u);
}

TEST(GateIoSim, GateFramesHideCornersBehindTheirBars) {
  const sim::Scene& scene = *tinyRace().simulator->scene();
  const sim::Gate& gate = scene.gates()[0];
  const Vec3 x = gate.R_WG.col(0), y = gate.R_WG.col(1);
  for (int k = 0; k < 4; ++k)  // straight in front of the opening: all four corners
    EXPECT_TRUE(sim::gateCornerVisible(scene, gate, k, gate.center - 5.0 * x)) << k;
  // Behind the gate and far to its left (+y): the left bar hides the left corners' front edge,
  // the right corners are seen through the opening.
  const Vec3 behind_left = gate.center + 0.3 * x + 2.0 * y;
  EXPECT_FALSE(sim::gateCornerVisible(scene, gate, 0, behind_left));
  EXPECT_FALSE(sim::gateCornerVisible(scene, gate, 3, behind_left));
  EXPECT_TRUE(sim::gateCornerVisible(scene, gate, 1, behind_left));
  EXPECT_TRUE(sim::gateCornerVisible(scene, gate, 2, behind_left));
}

TEST(GateIoSim, TracksTheTruthFromTheTrueStart) {
  const Sequence& seq = tinyRace().result.sequence;
  const ImoRunOutput out = runOnRace(raceOptions(), truthAt(seq, 0), true);
  ASSERT_EQ(out.states.size(), seq.imu.size());
  const double rmse = positionRmse(seq, out.states, 0.0);
  std::printf("gate_io on ci_race_tiny from the true start: position RMSE %.4f m, %d frames (%ld corners), %d gated out\n",
              rmse, out.frames_applied, out.corners_used, out.frames_rejected);
  EXPECT_GT(out.frames_applied, 40);
  EXPECT_LE(out.frames_rejected, 2);
  EXPECT_LT(rmse, 0.05);  // measured 0.011 m
}

TEST(GateIoSim, RecoversFromAWrongStartThatDeadReckoningKeeps) {
  const Sequence& seq = tinyRace().result.sequence;
  NavState init = truthAt(seq, 0);
  init.T_WB.p += Vec3(0.3, -0.2, 0.1);
  init.v_W += Vec3(0.0, 0.3, 0.0);
  init.T_WB.q = init.T_WB.q * quatExp(Vec3(0.0, 0.0, 3.0 * M_PI / 180.0));
  InertialEstimatorOptions o = raceOptions();
  o.run.filter.init_position_sigma = 0.5;
  o.run.filter.init_velocity_sigma = 0.5;
  o.run.filter.init_yaw_sigma = 5.0 * M_PI / 180.0;
  const ImoRunOutput gated = runOnRace(o, init, true);
  const ImoRunOutput dead = runOnRace(o, init, false);
  const double rmse_gate = positionRmse(seq, gated.states, 3.0);
  const double rmse_dead = positionRmse(seq, dead.states, 3.0);
  std::printf("wrong start, last second: gate_io %.4f m, IMU dead reckoning %.4f m\n", rmse_gate, rmse_dead);
  EXPECT_LT(rmse_gate, 0.1);
  EXPECT_GT(rmse_dead, 10.0 * rmse_gate);
}

TEST(GateIoSim, FusesDisplacementsOnTheCloneGrid) {
  // A ground-truth displacement source (1 cm sigma) alongside the gates: exercises the clone
  // bookkeeping and the update order at coinciding frame and grid times.
  const Race& race = tinyRace();
  const Sequence& seq = race.result.sequence;
  auto position_at = [&seq](Timestamp t) {
    const auto it = std::lower_bound(seq.groundtruth.begin(), seq.groundtruth.end(), t,
                                     [](const GroundTruthState& s, Timestamp tt) { return s.t < tt; });
    EXPECT_EQ(it->t, t);  // the grid is on IMU samples here
    return it->T_WB.p;
  };
  int calls = 0;
  const DisplacementSource source = [&](const DisplacementRequest& r) -> std::optional<DisplacementEstimate> {
    ++calls;
    EXPECT_EQ(r.t_end - r.t_begin, fromSeconds(0.5));
    DisplacementEstimate e;
    e.z = position_at(r.t_end) - position_at(r.t_begin);
    e.covariance = 1e-4 * Mat3::Identity();
    return e;
  };
  InertialEstimatorOptions o = raceOptions();
  o.displacement = DisplacementUse::kFilterUpdate;
  o.run.update_rate_hz = 20.0;
  o.run.window_s = 0.5;
  NavState init = truthAt(seq, 0);
  init.v_W += Vec3(0.2, 0.0, 0.0);  // the displacements must correct this before the first gate
  const std::vector<GateFrame> frames = hdvio::gateFrames(race.result.gates);
  const ImoRunOutput fused = runRace(o, init, frames, source);
  o.displacement = DisplacementUse::kNone;
  const ImoRunOutput gates_only = runRace(o, init, frames);
  // 80 grid times, the first 9 without a full window.
  EXPECT_EQ(calls, 71);
  EXPECT_EQ(fused.updates, 71);
  EXPECT_EQ(fused.frames_applied, gates_only.frames_applied);
  const double rmse_fused = positionRmse(seq, fused.states, 0.0);
  const double rmse_gates = positionRmse(seq, gates_only.states, 0.0);
  std::printf("velocity error 0.2 m/s at start: gates + true displacements %.4f m, gates only %.4f m\n",
              rmse_fused, rmse_gates);
  EXPECT_LT(rmse_fused, 0.05);
  EXPECT_LT(rmse_fused, rmse_gates);  // no gate in view for the first 1.8 s
  EXPECT_THROW(runRace([&] { InertialEstimatorOptions b = o; b.displacement = DisplacementUse::kFilterUpdate; return b; }(),
                         init, frames),
               std::invalid_argument);
}

TEST(GateIoSim, PerCornerGateRejectsOutlierDetections) {
  // Every 7th detection after the first 0.7 s of gates moved by 25 px: without a gate they pull
  // the estimate away; the per-corner gate drops them (and almost nothing else). (While the
  // filter is still uncertain, right after 1.8 s of dead reckoning, an outlier passes any gate:
  // with outliers from the first frame on, this flight loses track; docs/gate_io.md.)
  const Race& race = tinyRace();
  const Sequence& seq = race.result.sequence;
  io::GateData corrupted = race.result.gates;
  int outliers = 0;
  for (std::size_t i = 0; i < corrupted.detections.size(); i += 7) {
    if (secondsBetween(race.config.start_time_ns, corrupted.detections[i].t) < 2.5) continue;
    corrupted.detections[i].u += 25.0 * (i % 2 == 0 ? 1.0 : -1.0);
    corrupted.detections[i].v += 15.0;
    ++outliers;
  }
  const std::vector<GateFrame> frames = hdvio::gateFrames(corrupted);
  InertialEstimatorOptions o = raceOptions();
  o.gate->options.gate_probability = -1.0;
  const ImoRunOutput plain = runRace(o, truthAt(seq, 0), frames);
  o.gate->options.corner_gate_probability = 0.999;
  const ImoRunOutput gated = runRace(o, truthAt(seq, 0), frames);
  const double rmse_plain = positionRmse(seq, plain.states, 0.0);
  const double rmse_gated = positionRmse(seq, gated.states, 0.0);
  std::printf("%d outliers: no gate %.4f m, per-corner gate %.4f m (%ld corners gated out)\n", outliers,
              rmse_plain, rmse_gated, gated.corners_rejected);
  EXPECT_GE(gated.corners_rejected, outliers - 2);
  EXPECT_LE(gated.corners_rejected, outliers + 4);
  EXPECT_LT(rmse_gated, 0.03);
  EXPECT_GT(rmse_plain, 2.0 * rmse_gated);
}

}  // namespace
}  // namespace hdvio::imo
