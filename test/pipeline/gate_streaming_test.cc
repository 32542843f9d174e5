// The streaming example of gate_io: the tiny simulated race fed sample by sample (IMU, thrust
// 30 ms late, gate frames; merged in time order) through the public InertialEstimator with gate
// updates, as a live
// program would, gives the trajectory hdvio_run writes for the same race and experiment, byte
// for byte in hdvio_run's format: config/experiments/gate_io.yaml (gate updates only) and
// gate_io_network.yaml (with the shipped displacement network, whose windows wait for the
// thrust). The estimate lags the stream by one IMU sample, never more.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "../common/file_text.h"
#include "../common/result_text.h"
#include "../common/run_command.h"
#include "hdvio/core/config.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/gate_corners.h"
#include "hdvio/io/sequence_reader.h"
#include "hdvio/learned/displacement_model.h"
#include "hdvio/pipeline/displacement_network_source.h"
#include "hdvio/pipeline/inertial_estimator.h"
#include "hdvio/pipeline/inertial_sequence_runner.h"
#include "hdvio/sim/simulator.h"

namespace hdvio {
namespace {
namespace fs = std::filesystem;

// The experiment's gate and filter options, read as hdvio_run reads them (backend
// imo_filter_section.cc: the sigmas of the attitude in degrees).
InertialEstimatorOptions optionsOf(const ConfigReader& cfg, const CameraModel& camera, const Pose& T_BC) {
  InertialEstimatorOptions o;
  o.displacement = DisplacementUse::kNone;
  o.gate = GateCornerUpdates{imo::GateCornerOptions{}, camera, T_BC};
  const ConfigReader g = cfg.section("gate");
  g.readOptional("pixel_sigma", &o.gate->options.pixel_sigma);
  g.readOptional("gate_probability", &o.gate->options.gate_probability);
  const ConfigReader f = cfg.section("filter");
  imo::ImoFilterOptions& fo = o.run.filter;
  f.readOptional("gyro_noise_density", &fo.gyro_noise_density);
  f.readOptional("accel_noise_density", &fo.accel_noise_density);
  f.readOptional("gyro_random_walk", &fo.gyro_random_walk);
  f.readOptional("accel_random_walk", &fo.accel_random_walk);
  double att_deg = 0.0, yaw_deg = 0.0;
  f.read("init_attitude_sigma_deg", &att_deg);
  f.read("init_yaw_sigma_deg", &yaw_deg);
  fo.init_attitude_sigma = att_deg * M_PI / 180.0;
  fo.init_yaw_sigma = yaw_deg * M_PI / 180.0;
  f.readOptional("init_velocity_sigma", &fo.init_velocity_sigma);
  f.readOptional("init_position_sigma", &fo.init_position_sigma);
  f.readOptional("init_gyro_bias_sigma", &fo.init_gyro_bias_sigma);
  f.readOptional("init_accel_bias_sigma", &fo.init_accel_bias_sigma);
  f.readOptional("update_rate_hz", &o.run.update_rate_hz);
  f.readOptional("use_source_covariance", &o.run.use_source_covariance);
  return o;
}

// One measurement of the merged stream; at equal times IMU, then thrust, then the frame.
struct Event {
  Timestamp t = 0;
  int kind = 0;  // 0 IMU, 1 thrust, 2 gate frame
  std::size_t index = 0;
};

class GateStreaming : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / ("hdvio_gate_streaming_" + std::to_string(getpid())));
    fs::remove_all(*dir_);
    sim::SimConfig config = sim::loadSimConfig(
        ConfigReader::fromFile(std::string(HDVIO_SOURCE_DIR) + "/config/sim/ci_race_tiny.yaml"));
    config.scene.num_landmarks = 0;
    const sim::Simulator simulator(config);
    const sim::SimulationResult race = simulator.simulate();
    io::writeAsl(race.sequence, (*dir_ / "race").string());
    io::writeGateData(race.gates, (*dir_ / "race" / "mav0").string());
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }

  // hdvio_run with the experiment, then the same race streamed through an InertialEstimator.
  void expectStreamingMatchesHdvioRun(const std::string& experiment) {
    const std::string config = std::string(HDVIO_SOURCE_DIR) + "/config/experiments/" + experiment;
    const fs::path out = *dir_ / ("out_" + experiment);
    const std::string dataset = (*dir_ / "race").string();
    const test::CommandOutcome run = test::runCommand(std::string(HDVIO_RUN_BINARY) + " --config " + config +
                                                      " --dataset " + dataset + " --evaluate=false --out " +
                                                      out.string());
    ASSERT_EQ(run.exit_code, 0) << run.output;

    const Sequence seq = io::readSequence(dataset);
    const ConfigReader cfg = ConfigReader::fromFile(config);
    InertialEstimatorOptions options = optionsOf(cfg, CameraModel::fromCalibration(*seq.camera), seq.camera->T_BS);
    DisplacementSourceFactory source;
    if (cfg.has("network")) {
      std::string weights;
      cfg.section("network").read("weights", &weights);
      const auto model = std::make_shared<const learned::DisplacementModel>(
          learned::DisplacementModel::load((fs::path(config).parent_path() / weights).string()));
      options.displacement = DisplacementUse::kFilterUpdate;
      options.run.window_s = model->windowSeconds();
      options.source_needs_thrust = model->inputKind() == learned::DisplacementInputKind::kThrustGyro;
      ASSERT_TRUE(options.source_needs_thrust);
      source = [model](const InertialBuffers& b) { return networkDisplacementSource(model, b.imu, b.thrust); };
    }

    const std::vector<imo::GateFrame> frames = gateFrames(io::readGateData(dataset));
    const std::vector<ThrustSample> thrust = thrustSamples(seq);
    ASSERT_GT(frames.size(), 40u);
    ASSERT_FALSE(thrust.empty());
    // hdvio_run starts at the first IMU sample with ground truth, from the true state.
    const auto first = std::lower_bound(seq.imu.begin(), seq.imu.end(), seq.groundtruth.front().t,
                                        [](const ImuSample& s, Timestamp t) { return s.t < t; });
    ASSERT_NE(first, seq.imu.end());
    NavState init = groundTruthState(seq, first->t);
    init.bias.setZero();

    const Timestamp latency = fromSeconds(0.03);  // thrust arrives behind the IMU
    std::vector<Event> events;
    for (std::size_t k = 0; k < seq.imu.size(); ++k) events.push_back({seq.imu[k].t, 0, k});
    for (std::size_t k = 0; k < thrust.size(); ++k) events.push_back({thrust[k].t + latency, 1, k});
    for (std::size_t k = 0; k < frames.size(); ++k) events.push_back({frames[k].t, 2, k});
    std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
      return a.t != b.t ? a.t < b.t : a.kind < b.kind;
    });

    const bool fusing = options.displacement == DisplacementUse::kFilterUpdate;
    InertialEstimator estimator(options, source);
    Timestamp previous_imu = -1;
    int lagging = 0;
    for (const Event& e : events) {
      if (e.kind == 1) estimator.addThrust(thrust[e.index]);
      if (e.kind == 2) estimator.addFrame(frames[e.index]);
      if (e.kind != 0) continue;
      estimator.addImu(seq.imu[e.index]);
      if (e.t == init.t) estimator.initialize(init);
      // Without the network: the state of the sample before this one. With it, a sample at an
      // update time also waits the 30 ms for its thrust.
      if (estimator.initialized() && e.t > init.t + latency + fromSeconds(0.01) &&
          estimator.state().t != previous_imu)
        ++lagging;
      previous_imu = e.t;
    }
    estimator.finish();
    if (fusing) {
      EXPECT_GT(lagging, 0);  // the thrust wait is real
    } else {
      EXPECT_EQ(lagging, 0);
    }
    const imo::ImoRunOutput& result = estimator.output();
    EXPECT_EQ(result.states.size(), static_cast<std::size_t>(seq.imu.end() - first));
    EXPECT_GT(result.frames_applied, 40);
    if (fusing) {
      EXPECT_GT(result.updates, 40);
    }

    EXPECT_TRUE(test::readFile(out / "stamped_traj_estimate.txt") == test::trajectoryText(result.states))
        << "trajectories differ";
    EXPECT_TRUE(test::withoutHeader(test::readFile(out / "stamped_velocity_estimate.csv")) ==
                test::velocityText(result.states))
        << "velocities differ";
  }

  static fs::path* dir_;
};
fs::path* GateStreaming::dir_ = nullptr;

TEST_F(GateStreaming, GateUpdatesSampleBySampleMatchHdvioRunByteForByte) {
  expectStreamingMatchesHdvioRun("gate_io.yaml");
}

TEST_F(GateStreaming, GateUpdatesWithNetworkSampleBySampleMatchHdvioRunByteForByte) {
  expectStreamingMatchesHdvioRun("gate_io_network.yaml");
}

}  // namespace
}  // namespace hdvio
