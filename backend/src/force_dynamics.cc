#include "force_dynamics.h"

#include "hdvio/factors/dynamics_factors.h"
#include "hdvio/factors/prior_factors.h"

namespace hdvio {
using symbols::B;
using symbols::F;
using symbols::V;
using symbols::X;

ForceDynamics::ForceDynamics(const VioBackendOptions& options) : options_(options) {}

std::vector<Key> ForceDynamics::stateKeys(std::uint64_t index) const { return {F(index)}; }

void ForceDynamics::addFirstState(std::uint64_t index, const NavState& s, const InertialBuffers& in,
                                  FactorGraph* priors, Values* values) const {
  const Vec3 f0 = firstForce(s, in);
  values->insertVector(F(index), f0);
  priors->add(std::make_shared<ForcePrior>(F(index), f0,
                                           NoiseModel::isotropic(3, options_.init_force_sigma)));
}

void ForceDynamics::readState(const Values& estimate, std::uint64_t index, NavState* s) const {
  s->f_ext_W = estimate.vec3(F(index));
}

std::shared_ptr<const PreintegratedThrust> ForceDynamics::preintegrate(
    const StateInterval& interval, const InertialBuffers& in, const ResidualForceFn& force,
    Values* values) const {
  const NavState& s = interval.state_i;
  auto pit = std::make_shared<const PreintegratedThrust>(PreintegratedThrust::integrate(
      in.imu, in.thrust, interval.t_i, interval.t_j, s.bias, options_.thrust, force));
  values->insertVector(F(interval.j), s.f_ext_W);
  return pit;
}

DynamicsFactorParams ForceDynamics::intervalParams(const StateInterval& interval) const {
  const NavState& s = interval.state_i;
  const Mat3 Ri = s.T_WB.R();
  DynamicsFactorParams params = options_.dynamics;
  params.sigma_velocity_i = Ri.transpose() * s.v_W;
  params.sigma_velocity_j = Ri.transpose() * interval.v_j;
  return params;
}

namespace {
// vimo and vid: the force is held on F_i over [i, j] with a prior on it (the factor class says
// around what), so F(j) enters with the next interval's factor.
template <class Factor>
class ForcePriorDynamics final : public ForceDynamics {
 public:
  using ForceDynamics::ForceDynamics;

  void addInterval(const StateInterval& iv, const InertialBuffers& in, FactorGraph* graph,
                   Values* values) override {
    auto pit = preintegrate(iv, in, ResidualForceFn(), values);
    const DynamicsFactorParams params = intervalParams(iv);
    graph->add(std::make_shared<Factor>(X(iv.i), V(iv.i), F(iv.i), X(iv.j), V(iv.j), B(iv.i),
                                        pit, params));
  }

  // The newest F is not constrained yet: report the force of the interval ending there.
  void readNewest(const Values& estimate, std::uint64_t previous, NavState* s) const override {
    s->f_ext_W = estimate.vec3(F(previous));
  }
};
}  // namespace

std::unique_ptr<DynamicsModel> makeVimoDynamics(const VioBackendOptions& options) {
  return std::make_unique<ForcePriorDynamics<VimoDynamicsFactor>>(options);
}

std::unique_ptr<DynamicsModel> makeVidDynamics(const VioBackendOptions& options) {
  return std::make_unique<ForcePriorDynamics<VidDynamicsFactor>>(options);
}

}  // namespace hdvio
