#pragma once
// The part vimo, vid and hdvio share (dynamics_model.h): each state has an external force F(k)
// (world frame), the first one with a prior of sigma init_force_sigma, and the new F(j) starts
// at the estimate at i. Each family supplies its dynamics factor.
#include <memory>

#include "hdvio/backend/dynamics_model.h"
#include "hdvio/factors/point_mass_dynamics.h"
#include "hdvio/factors/thrust_preintegration.h"

namespace hdvio {

class ForceDynamics : public DynamicsModel {
 public:
  explicit ForceDynamics(const VioBackendOptions& options);

  bool needsThrust() const override { return true; }
  std::vector<Key> stateKeys(std::uint64_t index) const override;
  void addFirstState(std::uint64_t index, const NavState& s, const InertialBuffers& in,
                     FactorGraph* priors, Values* values) const override;
  void readState(const Values& estimate, std::uint64_t index, NavState* s) const override;

 protected:
  // The first state's force prior mean.
  virtual Vec3 firstForce(const NavState& s, const InertialBuffers& in) const { return s.f_ext_W; }
  // The interval's preintegrated thrust (with the residual force, if any); inserts F(j) at the
  // force at i.
  std::shared_ptr<const PreintegratedThrust> preintegrate(const StateInterval& interval,
                                                          const InertialBuffers& in,
                                                          const ResidualForceFn& force,
                                                          Values* values) const;
  // The factor's noise settings, the drag law's sigma taken at the predicted body velocities.
  DynamicsFactorParams intervalParams(const StateInterval& interval) const;

  const VioBackendOptions& options() const { return options_; }

 private:
  VioBackendOptions options_;
};

// vimo (zero-mean force prior) and vid (prior at accelerometer minus thrust) hold the force on
// F_i over [i, j]; hdvio walks it from F_i to F_j with the learned force and drag law.
std::unique_ptr<DynamicsModel> makeVimoDynamics(const VioBackendOptions& options);
std::unique_ptr<DynamicsModel> makeVidDynamics(const VioBackendOptions& options);
std::unique_ptr<DynamicsModel> makeHdvioDynamics(const VioBackendOptions& options,
                                                 ResidualForceSource residual_force);

}  // namespace hdvio
