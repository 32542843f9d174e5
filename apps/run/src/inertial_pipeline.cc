// Inertial methods (imo, tlio, model_ekf, net_only): the IMO filter family (docs/imo.md).
//   imo       EKF + displacement network on thrust + gyro (Cioffi et al. 2023)
//   tlio      EKF + displacement network on accelerometer + gyro (TLIO-style)
//   model_ekf EKF + displacement of the thrust + linear drag model, no network
//   net_only  network displacements concatenated, no filter
// All start from the ground-truth state at the first IMU sample with ground truth.
#include <algorithm>
#include <memory>
#include <optional>

#include "hdvio/backend/imo/displacement_source.h"
#include "hdvio/backend/imo/drag_model.h"
#include "hdvio/backend/imo/imo_filter_section.h"
#include "hdvio/core/error.h"
#include "hdvio/core/sequence.h"
#include "hdvio/learned/displacement_model.h"
#include "hdvio/pipeline/displacement_network_loader.h"
#include "hdvio/pipeline/displacement_network_source.h"
#include "hdvio/pipeline/inertial_sequence_runner.h"
#include "hdvio/run/method_pipeline.h"
#include "hdvio/run/progress.h"

namespace hdvio::run {
namespace {

class InertialPipeline : public MethodPipeline {
 public:
  InertialPipeline(const std::string& method, const ConfigReader& cfg, const ExperimentFile& file)
      : method_(method), file_(file) {
    imo::ImoFilterSection filter{&options_, init_gyro_bias_, init_accel_bias_};
    imo::readImoFilterSection(cfg.optionalSection("filter"), file.path, &filter);
    init_gyro_bias_ = filter.init_gyro_bias;
    init_accel_bias_ = filter.init_accel_bias;
    release_first_window_sample_ = filter.release_first_window_sample;
    if (method_ == "model_ekf") {
      const ConfigReader m = cfg.optionalSection("model");
      m.readInRange("integration_step_s", &model_step_s_, 1e-4, 0.1);
      m.readInRange("window_s", &options_.window_s, 0.05, 5.0);
      m.readInRange("thrust_scale", &drag_model_.thrust_scale, 0.1, 10.0);
      drag_model_.drag.linear = readVec3(m, "linear_drag", drag_model_.drag.linear);
      m.readOptional("attitude_jacobian", &model_attitude_jacobian_);
      m.finish();
      if ((drag_model_.drag.linear.array() < 0.0).any())
        throw InputError(file.path, 0, "model.linear_drag must be >= 0");
    } else {
      std::string weights;
      model_ = loadDisplacementNetwork(cfg.section("network"), file.dir, &weights);
      const bool wants_thrust = method_ == "imo";
      const bool has_thrust_input =
          model_->inputKind() == learned::DisplacementInputKind::kThrustGyro;
      if ((method_ == "imo" || method_ == "tlio") && wants_thrust != has_thrust_input)
        throw InputError(file.path, 0,
                         "method " + method_ + " needs a " + (wants_thrust ? "thrust_gyro" : "accel_gyro") +
                             " network, " + weights + " is " + learned::toString(model_->inputKind()));
      options_.window_s = model_->windowSeconds();
      if (options_.use_source_covariance && !model_->hasCovariance())
        throw InputError(file.path, 0,
                         "filter.use_source_covariance is true but " + weights +
                             " has no covariance (output_sigma none); set filter.measurement_sigma instead");
    }
    const ConfigReader t = cfg.optionalSection("thrust");
    t.readInRange("coefficient_over_mass", &thrust_coefficient_over_mass_, 0.0, 1.0);
    thrust_axis_ = readVec3(t, "axis", thrust_axis_);
    t.finish();
    if (std::abs(thrust_axis_.norm() - 1.0) > 1e-6)
      throw InputError(file.path, 0, "thrust.axis must be a unit vector");
    const ConfigReader r = cfg.optionalSection("run");
    r.readInRange("start_offset_s", &start_offset_s_, 0.0, 1e6);
    r.readInRange("duration_s", &duration_s_, 0.0, 1e6);
    r.finish();
    try {
      imo::checkRunOptions(options_);
    } catch (const std::invalid_argument& e) {
      throw InputError(file.path, 0, e.what());
    }
  }

  RunResults run(const Sequence& seq) override {
    if (seq.imu.size() < 2) throw InputError(seq.source, 0, "method " + method_ + " needs IMU data");
    if (!seq.hasGroundTruth())
      throw InputError(seq.source, 0, "method " + method_ +
                                          " starts from the ground-truth state; the sequence has none");
    const std::vector<ThrustSample> thrust = thrustOf(seq);
    const bool needs_thrust =
        method_ == "model_ekf" ||
        (model_ && model_->inputKind() == learned::DisplacementInputKind::kThrustGyro);
    if (needs_thrust && thrust.empty())
      throw InputError(seq.source, 0,
                       "method " + method_ +
                           " needs collective thrust (thrust samples, rotor speeds with a rotor "
                           "calibration, or thrust.coefficient_over_mass in the config); the "
                           "sequence has none");

    // Start at the first IMU sample with ground truth (+ offset); optionally a limited span.
    const std::vector<ImuSample> imu = imuSpanWithGroundTruth(seq, start_offset_s_, duration_s_);
    NavState init = groundTruthState(seq, imu.front().t);
    if (!seq.groundtruth.front().has_velocity)
      throw InputError(seq.source, 0, "method " + method_ + " needs ground-truth velocity to start");
    init.bias << init_gyro_bias_, init_accel_bias_;

    InertialEstimatorOptions options;
    options.run = options_;
    options.displacement = method_ == "net_only" ? DisplacementUse::kConcatenate : DisplacementUse::kFilterUpdate;
    options.source_needs_thrust = needs_thrust;
    Progress progress(method_, imu.front().t, imu.back().t);
    const auto on_progress = [&progress](Timestamp t) { progress.update(t); };
    const imo::ImoRunOutput out =
        runInertialOnSequence(seq, thrust, {}, imu, init, options, sourceFactory(imu.front().t), on_progress);
    progress.finish();

    RunResults results;
    results.states = out.states;
    results.innovations = out.innovations;
    if (start_offset_s_ > 0.0 || duration_s_ > 0.0) results.input_span = {imu.front().t, imu.back().t};
    const int updates = out.updates + out.rejected + out.no_measurement;
    results.stages.push_back({"propagation", out.propagation_s, static_cast<int>(imu.size())});
    results.stages.push_back({model_ ? "network" : "model", out.source_s, updates});
    if (method_ != "net_only") results.stages.push_back({"update", out.update_s, updates});
    std::fprintf(stderr, "hdvio_run: %d updates applied, %d gated out, %d without measurement\n",
                 out.updates, out.rejected, out.no_measurement);
    return results;
  }

 private:
  std::vector<ThrustSample> thrustOf(const Sequence& seq) const {
    std::vector<ThrustSample> thrust = thrustSamples(seq);
    if (thrust.empty() && thrust_coefficient_over_mass_ > 0.0)
      for (const RotorSample& r : seq.rotor)
        thrust.push_back({r.t, thrust_coefficient_over_mass_ * r.speeds.squaredNorm() * thrust_axis_});
    return thrust;
  }

  // The displacement source over the estimator's buffers: the drag model or the network (start:
  // the first IMU sample, for release_first_window_sample).
  DisplacementSourceFactory sourceFactory(Timestamp start) const {
    if (!model_)
      return [this](const InertialBuffers& b) {
        return imo::makeDragModelSource(b.thrust, drag_model_, model_step_s_,
                                        options_.measurement_sigma, options_.filter.gravity,
                                        model_attitude_jacobian_);
      };
    const std::optional<Timestamp> repeat =
        release_first_window_sample_ ? std::optional<Timestamp>(start) : std::nullopt;
    return [model = model_, repeat](const InertialBuffers& b) {
      return networkDisplacementSource(model, b.imu, b.thrust, repeat);
    };
  }

  std::string method_;
  ExperimentFile file_;
  imo::ImoRunOptions options_;
  std::shared_ptr<const learned::DisplacementModel> model_;
  double model_step_s_ = 0.005;
  imo::DragModel drag_model_;             // model_ekf: thrust scale and linear drag
  bool model_attitude_jacobian_ = true;   // model_ekf: attitude Jacobian of the model displacement
  double thrust_coefficient_over_mass_ = 0.0;
  Vec3 thrust_axis_ = Vec3::UnitZ();
  Vec3 init_gyro_bias_ = Vec3::Zero();
  Vec3 init_accel_bias_ = Vec3::Zero();
  bool release_first_window_sample_ = false;
  double start_offset_s_ = 0.0;
  double duration_s_ = 0.0;
};

}  // namespace

const std::vector<std::string>& inertialMethods() {
  static const std::vector<std::string> kMethods = {"imo", "tlio", "model_ekf", "net_only", "gate_io"};
  return kMethods;
}

std::unique_ptr<MethodPipeline> makeInertialPipeline(const std::string& method,
                                                     const ConfigReader& cfg,
                                                     const ExperimentFile& file) {
  if (method == "gate_io") return makeGateIoPipeline(cfg, file);
  return std::make_unique<InertialPipeline>(method, cfg, file);
}

}  // namespace hdvio::run
