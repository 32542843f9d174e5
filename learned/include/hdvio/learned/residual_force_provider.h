#pragma once
// How the smoother obtains residual forces for the dynamics preintegration over [t_i, t_j]:
// the zero provider (VIMO: the thrust model alone, the residual is left to the estimator) and
// the TCN provider (HDVIO). learned/ depends on core only; the backend glues providers to the
// PreintegratedThrust of factors/.
#include <memory>
#include <string>
#include <vector>

#include "hdvio/core/config.h"
#include "hdvio/core/sequence.h"
#include "hdvio/learned/residual_force_model.h"

namespace hdvio::learned {

struct ResidualForce {
  Timestamp t = 0;
  Vec3 force = Vec3::Zero();       // mass-normalized, body frame, m/s^2
  Mat3 covariance = Mat3::Zero();  // (m/s^2)^2
};

class ResidualForceProvider {
 public:
  virtual ~ResidualForceProvider() = default;
  virtual std::string name() const = 0;
  // Input history the provider wants before t_i (the caller passes samples from
  // t_i - historySeconds() on, or from the start of the flight).
  virtual double historySeconds() const = 0;
  // samples: time-ordered thrust + raw gyroscope samples reaching at least t_j. Returns one
  // residual force per sample with t_i <= t <= t_j, in sample order. Throws
  // std::invalid_argument if samples are unordered or t_i > t_j.
  virtual std::vector<ResidualForce> residualForces(const std::vector<DynamicsInput>& samples,
                                                    Timestamp t_i, Timestamp t_j,
                                                    const Vec3& gyro_bias) const = 0;
  // The drag law the provider's forces complement (the dynamics add it at the state's
  // velocity); none by default.
  virtual DragLaw dragLaw() const { return {}; }
  // The least random walk (m/s^2/sqrt(s)) of the external force the model's error needs
  // (ResidualForceModel::forceWalk); 0 by default.
  virtual double forceWalk() const { return 0.0; }
  // What the model saw in training (ResidualForceModel::envelope); unbounded by default.
  virtual ModelEnvelope envelope() const { return {}; }
};

// VIMO: no learned force; zero force with zero covariance.
class ZeroResidualForceProvider final : public ResidualForceProvider {
 public:
  std::string name() const override { return "zero"; }
  double historySeconds() const override { return 0.0; }
  std::vector<ResidualForce> residualForces(const std::vector<DynamicsInput>& samples,
                                            Timestamp t_i, Timestamp t_j,
                                            const Vec3& gyro_bias) const override;
};

// HDVIO: the TCN evaluated on the window ending at each sample.
class TcnResidualForceProvider final : public ResidualForceProvider {
 public:
  explicit TcnResidualForceProvider(std::shared_ptr<const ResidualForceModel> model);
  std::string name() const override { return "tcn"; }
  double historySeconds() const override { return model_->windowSeconds(); }
  std::vector<ResidualForce> residualForces(const std::vector<DynamicsInput>& samples,
                                            Timestamp t_i, Timestamp t_j,
                                            const Vec3& gyro_bias) const override;
  const ResidualForceModel& model() const { return *model_; }
  DragLaw dragLaw() const override { return model_->dragLaw(); }
  double forceWalk() const override { return model_->forceWalk(); }
  ModelEnvelope envelope() const override { return model_->envelope(); }

 private:
  std::shared_ptr<const ResidualForceModel> model_;
};

// Diagnostics on simulated flights: the sequence's true drag force (ForceSample::drag, linear
// between samples) at each sample, i.e. a perfect residual-force model, the upper bound of
// what a learned model can give the estimator (the external force is left to it, as for the
// TCN). Throws std::invalid_argument if forces is empty or not strictly increasing in time.
class GroundTruthResidualForceProvider final : public ResidualForceProvider {
 public:
  explicit GroundTruthResidualForceProvider(std::vector<ForceSample> forces);
  std::string name() const override { return "ground_truth"; }
  double historySeconds() const override { return 0.0; }
  std::vector<ResidualForce> residualForces(const std::vector<DynamicsInput>& samples,
                                            Timestamp t_i, Timestamp t_j,
                                            const Vec3& gyro_bias) const override;

 private:
  std::vector<ForceSample> forces_;
};

// Glue for the smoother: thrust samples with t_from <= t <= t_to, each paired with the raw
// gyroscope linearly interpolated at its time (samples outside the IMU span are skipped).
std::vector<DynamicsInput> makeDynamicsInputs(const std::vector<ImuSample>& imu,
                                              const std::vector<ThrustSample>& thrust,
                                              Timestamp t_from, Timestamp t_to);
// Provider output as a function of time (linear between samples, held beyond the ends), the
// shape of factors' ResidualForceFn. Throws std::invalid_argument if forces is empty.
Vec3 residualForceAt(const std::vector<ResidualForce>& forces, Timestamp t);

// From a config section:
//   type: zero | tcn          (required; ground_truth is built by the caller, which has the
//                              sequence: see GroundTruthResidualForceProvider)
//   weights: <path>           (tcn only; relative paths are taken relative to base_dir)
//   default_sigma: 0.3        (tcn only; m/s^2, used when the network has no variance head)
// Calls finish() on the section. Throws InputError on bad keys or a bad weight file.
std::unique_ptr<ResidualForceProvider> makeResidualForceProvider(const ConfigReader& section,
                                                                 const std::string& base_dir = "");

}  // namespace hdvio::learned
