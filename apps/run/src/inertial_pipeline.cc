// Inertial methods (imo, tlio, model_ekf, net_only): the IMO filter family (docs/imo.md).
//   imo       EKF + displacement network on thrust + gyro (Cioffi et al. 2023)
//   tlio      EKF + displacement network on accelerometer + gyro (TLIO-style)
//   model_ekf EKF + displacement of the thrust + linear drag model, no network
//   net_only  network displacements concatenated, no filter
// All start from the ground-truth state at the first IMU sample with ground truth.
#include <algorithm>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "hdvio/backend/imo/displacement_source.h"
#include "hdvio/backend/imo/drag_model_section.h"
#include "hdvio/backend/imo/imo_filter_section.h"
#include "hdvio/core/error.h"
#include "hdvio/core/sequence.h"
#include "hdvio/learned/displacement_model.h"
#include "hdvio/pipeline/displacement_network_loader.h"
#include "hdvio/pipeline/displacement_network_source.h"
#include "hdvio/pipeline/inertial_config_sections.h"
#include "hdvio/pipeline/inertial_sequence_runner.h"
#include "hdvio/run/method_pipeline.h"
#include "hdvio/run/progress.h"

namespace hdvio::run {
namespace {

// The method, decided once from its name (the name stays for messages).
enum class InertialMethod { kImo, kTlio, kModelEkf, kNetOnly };

InertialMethod parseInertialMethod(const std::string& name) {
  if (name == "imo") return InertialMethod::kImo;
  if (name == "tlio") return InertialMethod::kTlio;
  if (name == "model_ekf") return InertialMethod::kModelEkf;
  if (name == "net_only") return InertialMethod::kNetOnly;
  throw std::invalid_argument("unknown inertial method '" + name + "'");
}

class InertialPipeline : public MethodPipeline {
 public:
  InertialPipeline(const std::string& method, const ConfigReader& cfg, const ExperimentFile& file)
      : method_(parseInertialMethod(method)), name_(method), file_(file) {
    imo::ImoFilterSection filter{&options_, init_gyro_bias_, init_accel_bias_};
    imo::readImoFilterSection(cfg.optionalSection("filter"), file.path, &filter);
    init_gyro_bias_ = filter.init_gyro_bias;
    init_accel_bias_ = filter.init_accel_bias;
    release_first_window_sample_ = filter.release_first_window_sample;
    if (method_ == InertialMethod::kModelEkf) {
      drag_model_.window_s = options_.window_s;
      imo::readDragModelSection(cfg.optionalSection("model"), file.path, &drag_model_);
      options_.window_s = drag_model_.window_s;
    } else {
      std::string weights;
      model_ = loadDisplacementNetwork(cfg.section("network"), file.dir, &weights);
      const bool wants_thrust = method_ == InertialMethod::kImo;
      const bool has_thrust_input =
          model_->inputKind() == learned::DisplacementInputKind::kThrustGyro;
      if (method_ != InertialMethod::kNetOnly && wants_thrust != has_thrust_input)
        throw InputError(file.path, 0,
                         "method " + name_ + " needs a " + (wants_thrust ? "thrust_gyro" : "accel_gyro") +
                             " network, " + weights + " is " + learned::toString(model_->inputKind()));
      options_.window_s = model_->windowSeconds();
      if (options_.use_source_covariance && !model_->hasCovariance())
        throw InputError(file.path, 0,
                         "filter.use_source_covariance is true but " + weights +
                             " has no covariance (output_sigma none); set filter.measurement_sigma instead");
    }
    readThrustSection(cfg.optionalSection("thrust"), file.path, &rotor_thrust_);
    readInertialRunSection(cfg.optionalSection("run"), &span_);
    try {
      imo::checkRunOptions(options_);
    } catch (const std::invalid_argument& e) {
      throw InputError(file.path, 0, e.what());
    }
  }

  RunResults run(const Sequence& seq) override {
    if (seq.imu.size() < 2) throw InputError(seq.source, 0, "method " + name_ + " needs IMU data");
    if (!seq.hasGroundTruth())
      throw InputError(seq.source, 0, "method " + name_ +
                                          " starts from the ground-truth state; the sequence has none");
    const std::vector<ThrustSample> thrust = thrustOf(seq);
    const bool needs_thrust =
        method_ == InertialMethod::kModelEkf ||
        (model_ && model_->inputKind() == learned::DisplacementInputKind::kThrustGyro);
    if (needs_thrust && thrust.empty())
      throw InputError(seq.source, 0,
                       "method " + name_ +
                           " needs collective thrust (thrust samples, rotor speeds with a rotor "
                           "calibration, or thrust.coefficient_over_mass in the config); the "
                           "sequence has none");

    // Start at the first IMU sample with ground truth (+ offset); optionally a limited span.
    const std::vector<ImuSample> imu = imuSpanWithGroundTruth(seq, span_.start_offset_s, span_.duration_s);
    NavState init = groundTruthState(seq, imu.front().t);
    if (!seq.groundtruth.front().has_velocity)
      throw InputError(seq.source, 0, "method " + name_ + " needs ground-truth velocity to start");
    init.bias << init_gyro_bias_, init_accel_bias_;

    InertialEstimatorOptions options;
    options.run = options_;
    options.displacement =
        method_ == InertialMethod::kNetOnly ? DisplacementUse::kConcatenate : DisplacementUse::kFilterUpdate;
    options.source_needs_thrust = needs_thrust;
    Progress progress(name_, imu.front().t, imu.back().t);
    const auto on_progress = [&progress](Timestamp t) { progress.update(t); };
    const imo::ImoRunOutput out =
        runInertialOnSequence(seq, thrust, {}, imu, init, options, sourceFactory(imu.front().t), on_progress);
    progress.finish();

    RunResults results;
    results.states = out.states;
    results.innovations = out.innovations;
    if (span_.start_offset_s > 0.0 || span_.duration_s > 0.0)
      results.input_span = {imu.front().t, imu.back().t};
    const int updates = out.updates + out.rejected + out.no_measurement;
    results.stages.push_back({"propagation", out.propagation_s, static_cast<int>(imu.size())});
    results.stages.push_back({model_ ? "network" : "model", out.source_s, updates});
    if (method_ != InertialMethod::kNetOnly) results.stages.push_back({"update", out.update_s, updates});
    std::fprintf(stderr, "hdvio_run: %d updates applied, %d gated out, %d without measurement\n",
                 out.updates, out.rejected, out.no_measurement);
    return results;
  }

 private:
  std::vector<ThrustSample> thrustOf(const Sequence& seq) const {
    std::vector<ThrustSample> thrust = thrustSamples(seq);
    const RotorThrust& k = rotor_thrust_;
    if (thrust.empty() && k.coefficient_over_mass > 0.0)
      for (const RotorSample& r : seq.rotor)
        thrust.push_back({r.t, k.coefficient_over_mass * r.speeds.squaredNorm() * k.axis});
    return thrust;
  }

  // The displacement source over the estimator's buffers: the drag model or the network (start:
  // the first IMU sample, for release_first_window_sample).
  DisplacementSourceFactory sourceFactory(Timestamp start) const {
    if (!model_)
      return [this](const InertialBuffers& b) {
        return imo::makeDragModelSource(b.thrust, drag_model_.model, drag_model_.integration_step_s,
                                        options_.measurement_sigma, options_.filter.gravity,
                                        drag_model_.attitude_jacobian);
      };
    const std::optional<Timestamp> repeat =
        release_first_window_sample_ ? std::optional<Timestamp>(start) : std::nullopt;
    return [model = model_, repeat](const InertialBuffers& b) {
      return networkDisplacementSource(model, b.imu, b.thrust, repeat);
    };
  }

  InertialMethod method_;
  std::string name_;  // as in the config, for messages
  ExperimentFile file_;
  imo::ImoRunOptions options_;
  std::shared_ptr<const learned::DisplacementEnsemble> model_;  // one network or an ensemble
  imo::DragModelSection drag_model_;  // model_ekf: the model and its integration
  RotorThrust rotor_thrust_;
  Vec3 init_gyro_bias_ = Vec3::Zero();
  Vec3 init_accel_bias_ = Vec3::Zero();
  bool release_first_window_sample_ = false;
  InertialRunSpan span_;
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
