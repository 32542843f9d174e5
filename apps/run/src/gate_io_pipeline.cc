// gate_io (docs/gate_io.md): the IMO error-state EKF propagated with the IMU and
// corrected at every camera frame by the reprojections of known race-gate corners, read from
// the sequence's gates0/ and gate_corners0/ (simulated races). `displacement: network` also
// fuses a displacement network's relative-position measurements as the imo method does.
// Starts from the ground-truth state at the first IMU sample with ground truth.
#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>

#include "hdvio/backend/imo/imo_filter_section.h"
#include "hdvio/core/error.h"
#include "hdvio/core/sequence.h"
#include "hdvio/io/gate_corners.h"
#include "hdvio/pipeline/displacement_network_loader.h"
#include "hdvio/pipeline/displacement_network_source.h"
#include "hdvio/learned/displacement_model.h"
#include "hdvio/pipeline/inertial_sequence_runner.h"
#include "hdvio/run/method_pipeline.h"
#include "hdvio/run/progress.h"

namespace hdvio::run {
namespace {

class GateIoPipeline : public MethodPipeline {
 public:
  GateIoPipeline(const ConfigReader& cfg, const ExperimentFile& file) : file_(file) {
    std::string displacement = "none";
    cfg.readChoice("displacement", &displacement, {"none", "network"});
    fuse_displacements_ = displacement == "network";
    const ConfigReader g = cfg.optionalSection("gate");
    g.readInRange("pixel_sigma", &gate_.pixel_sigma, 1e-3, 100.0);
    g.readInRange("gate_probability", &gate_.gate_probability, -1.0, 0.999999);
    g.readInRange("corner_gate_probability", &gate_.corner_gate_probability, -1.0, 0.999999);
    g.readOptional("use_detections", &use_detections_);
    g.finish();
    imo::ImoFilterSection filter{&run_, init_gyro_bias_, init_accel_bias_};
    imo::readImoFilterSection(cfg.optionalSection("filter"), file.path, &filter);
    init_gyro_bias_ = filter.init_gyro_bias;
    init_accel_bias_ = filter.init_accel_bias;
    release_first_window_sample_ = filter.release_first_window_sample;
    if (fuse_displacements_) {
      model_ = loadDisplacementNetwork(cfg.section("network"), file.dir);
      run_.window_s = model_->windowSeconds();
      try {
        imo::checkRunOptions(run_);
      } catch (const std::invalid_argument& e) {
        throw InputError(file.path, 0, e.what());
      }
    } else if (cfg.has("network")) {
      throw InputError(file.path, 0, "network is only used with displacement: network");
    }
    const ConfigReader r = cfg.optionalSection("run");
    r.readInRange("start_offset_s", &start_offset_s_, 0.0, 1e6);
    r.readInRange("duration_s", &duration_s_, 0.0, 1e6);
    r.finish();
  }

  RunResults run(const Sequence& seq) override {
    if (seq.imu.size() < 2) throw InputError(seq.source, 0, "method gate_io needs IMU data");
    if (!seq.camera) throw InputError(seq.source, 0, "method gate_io needs the cam0 calibration");
    if (!seq.hasGroundTruth() || !seq.groundtruth.front().has_velocity)
      throw InputError(seq.source, 0, "method gate_io starts from the ground-truth state (with velocity); the sequence has none");
    // use_detections: false is the IMU-only (dead-reckoning) baseline: no gate files needed.
    const std::vector<imo::GateFrame> frames =
        use_detections_ ? gateFrames(io::readGateData(seq.source)) : std::vector<imo::GateFrame>{};
    const std::vector<ThrustSample> thrust = thrustSamples(seq);
    if (model_ && model_->inputKind() == learned::DisplacementInputKind::kThrustGyro && thrust.empty())
      throw InputError(seq.source, 0, "the thrust_gyro network needs collective thrust; the sequence has none");

    const std::vector<ImuSample> imu = imuSpanWithGroundTruth(seq, start_offset_s_, duration_s_);
    NavState init = groundTruthState(seq, imu.front().t);
    init.bias << init_gyro_bias_, init_accel_bias_;

    const CameraModel camera = CameraModel::fromCalibration(*seq.camera);
    Progress progress("gate_io", imu.front().t, imu.back().t);
    const auto on_progress = [&progress](Timestamp t) { progress.update(t); };
    InertialEstimatorOptions options;
    options.run = run_;
    options.displacement = fuse_displacements_ ? DisplacementUse::kFilterUpdate : DisplacementUse::kNone;
    options.gate = GateCornerUpdates{gate_, camera, seq.camera->T_BS};
    options.source_needs_thrust = model_ && model_->inputKind() == learned::DisplacementInputKind::kThrustGyro;
    const imo::ImoRunOutput out =
        runInertialOnSequence(seq, thrust, frames, imu, init, options, sourceFactory(imu.front().t), on_progress);
    progress.finish();

    RunResults results;
    results.states = out.states;
    results.stages.push_back({"propagation", out.propagation_s, static_cast<int>(imu.size())});
    results.stages.push_back({"gate_update", out.gate_update_s, out.frames_applied + out.frames_rejected});
    if (fuse_displacements_) {
      const int n = out.updates + out.rejected + out.no_measurement;
      results.stages.push_back({"network", out.source_s, n});
      results.stages.push_back({"displacement_update", out.update_s, n});
    }
    std::fprintf(stderr,
                 "hdvio_run: gate updates: %d frames applied (%ld corners), %d gated out, %zu frames "
                 "with detections, mean chi2 per dof %.2f, %ld corners gated out\n",
                 out.frames_applied, out.corners_used, out.frames_rejected, frames.size(),
                 out.mean_chi2_per_dof, out.corners_rejected);
    if (fuse_displacements_)
      std::fprintf(stderr, "hdvio_run: displacements: %d applied, %d gated out, %d without measurement\n",
                   out.updates, out.rejected, out.no_measurement);
    return results;
  }

 private:
  // The displacement network over the estimator's buffers, as in the imo method (none without
  // a network).
  DisplacementSourceFactory sourceFactory(Timestamp start) const {
    if (!model_) return {};
    const std::optional<Timestamp> release =
        release_first_window_sample_ ? std::optional<Timestamp>(start) : std::nullopt;
    return [model = model_, release](const InertialBuffers& b) {
      return networkDisplacementSource(model, b.imu, b.thrust, release);
    };
  }

  ExperimentFile file_;
  imo::ImoRunOptions run_;         // filter noise and initial covariance; grid/window for displacements
  imo::GateCornerOptions gate_;
  bool fuse_displacements_ = false;
  std::shared_ptr<const learned::DisplacementModel> model_;
  Vec3 init_gyro_bias_ = Vec3::Zero();
  Vec3 init_accel_bias_ = Vec3::Zero();
  bool release_first_window_sample_ = false;
  bool use_detections_ = true;
  double start_offset_s_ = 0.0;
  double duration_s_ = 0.0;
};

}  // namespace

std::unique_ptr<MethodPipeline> makeGateIoPipeline(const ConfigReader& cfg, const ExperimentFile& file) {
  return std::make_unique<GateIoPipeline>(cfg, file);
}

}  // namespace hdvio::run
