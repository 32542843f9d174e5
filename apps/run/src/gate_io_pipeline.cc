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

#include "hdvio/backend/imo/gate_corner_section.h"
#include "hdvio/backend/imo/imo_filter_section.h"
#include "hdvio/core/error.h"
#include "hdvio/core/sequence.h"
#include "hdvio/io/gate_corners.h"
#include "hdvio/pipeline/displacement_network_loader.h"
#include "hdvio/pipeline/displacement_network_source.h"
#include "hdvio/learned/displacement_model.h"
#include "hdvio/pipeline/inertial_config_sections.h"
#include "hdvio/pipeline/inertial_sequence_runner.h"
#include "hdvio/run/method_pipeline.h"
#include "hdvio/run/progress.h"

namespace hdvio::run {
namespace {

class GateIoPipeline : public MethodPipeline {
 public:
  GateIoPipeline(const ConfigReader& cfg, const ExperimentFile& file) : file_(file) {
    displacement_ = readGateIoDisplacement(cfg);
    imo::readGateCornerSection(cfg.optionalSection("gate"), &gate_);
    imo::ImoFilterSection filter{&run_, init_gyro_bias_, init_accel_bias_};
    imo::readImoFilterSection(cfg.optionalSection("filter"), file.path, &filter);
    init_gyro_bias_ = filter.init_gyro_bias;
    init_accel_bias_ = filter.init_accel_bias;
    release_first_window_sample_ = filter.release_first_window_sample;
    if (fusesDisplacements()) {
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
    readInertialRunSection(cfg.optionalSection("run"), &span_);
  }

  RunResults run(const Sequence& seq) override {
    if (seq.imu.size() < 2) throw InputError(seq.source, 0, "method gate_io needs IMU data");
    if (!seq.camera) throw InputError(seq.source, 0, "method gate_io needs the cam0 calibration");
    if (!seq.hasGroundTruth() || !seq.groundtruth.front().has_velocity)
      throw InputError(seq.source, 0, "method gate_io starts from the ground-truth state (with velocity); the sequence has none");
    // use_detections: false is the IMU-only (dead-reckoning) baseline: no gate files needed.
    const std::vector<imo::GateFrame> frames =
        gate_.use_detections ? gateFrames(io::readGateData(seq.source)) : std::vector<imo::GateFrame>{};
    const std::vector<ThrustSample> thrust = thrustSamples(seq);
    if (model_ && model_->inputKind() == learned::DisplacementInputKind::kThrustGyro && thrust.empty())
      throw InputError(seq.source, 0, "the thrust_gyro network needs collective thrust; the sequence has none");

    const std::vector<ImuSample> imu = imuSpanWithGroundTruth(seq, span_.start_offset_s, span_.duration_s);
    NavState init = groundTruthState(seq, imu.front().t);
    init.bias << init_gyro_bias_, init_accel_bias_;

    const CameraModel camera = CameraModel::fromCalibration(*seq.camera);
    Progress progress("gate_io", imu.front().t, imu.back().t);
    const auto on_progress = [&progress](Timestamp t) { progress.update(t); };
    InertialEstimatorOptions options;
    options.run = run_;
    options.displacement = displacement_;
    options.gate = GateCornerUpdates{gate_.options, camera, seq.camera->T_BS};
    options.source_needs_thrust = model_ && model_->inputKind() == learned::DisplacementInputKind::kThrustGyro;
    const imo::ImoRunOutput out =
        runInertialOnSequence(seq, thrust, frames, imu, init, options, sourceFactory(imu.front().t), on_progress);
    progress.finish();

    RunResults results;
    results.states = out.states;
    results.stages.push_back({"propagation", out.propagation_s, static_cast<int>(imu.size())});
    results.stages.push_back({"gate_update", out.gate_update_s, out.frames_applied + out.frames_rejected});
    if (fusesDisplacements()) {
      const int n = out.updates + out.rejected + out.no_measurement;
      results.stages.push_back({"network", out.source_s, n});
      results.stages.push_back({"displacement_update", out.update_s, n});
    }
    std::fprintf(stderr,
                 "hdvio_run: gate updates: %d frames applied (%ld corners), %d gated out, %zu frames "
                 "with detections, mean chi2 per dof %.2f, %ld corners gated out\n",
                 out.frames_applied, out.corners_used, out.frames_rejected, frames.size(),
                 out.mean_chi2_per_dof, out.corners_rejected);
    if (fusesDisplacements())
      std::fprintf(stderr, "hdvio_run: displacements: %d applied, %d gated out, %d without measurement\n",
                   out.updates, out.rejected, out.no_measurement);
    return results;
  }

 private:
  bool fusesDisplacements() const { return displacement_ == DisplacementUse::kFilterUpdate; }

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
  imo::GateCornerSection gate_;    // corner update options, use_detections
  DisplacementUse displacement_ = DisplacementUse::kNone;  // kNone or kFilterUpdate (network)
  std::shared_ptr<const learned::DisplacementEnsemble> model_;  // one network or an ensemble
  Vec3 init_gyro_bias_ = Vec3::Zero();
  Vec3 init_accel_bias_ = Vec3::Zero();
  bool release_first_window_sample_ = false;
  InertialRunSpan span_;
};

}  // namespace

std::unique_ptr<MethodPipeline> makeGateIoPipeline(const ConfigReader& cfg, const ExperimentFile& file) {
  return std::make_unique<GateIoPipeline>(cfg, file);
}

}  // namespace hdvio::run
