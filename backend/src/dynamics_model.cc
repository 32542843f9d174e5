#include "hdvio/backend/dynamics_model.h"

#include <stdexcept>
#include <utility>

#include "force_dynamics.h"

namespace hdvio {

namespace {
// vio: reprojection and IMU factors only; no force is estimated (it reads as zero).
class NoDynamics final : public DynamicsModel {
 public:
  bool needsThrust() const override { return false; }
  std::vector<Key> stateKeys(std::uint64_t) const override { return {}; }
  void addFirstState(std::uint64_t, const NavState&, const InertialBuffers&, FactorGraph*,
                     Values*) const override {}
  void addInterval(const StateInterval&, const InertialBuffers&, FactorGraph*, Values*) override {}
  void readState(const Values&, std::uint64_t, NavState*) const override {}
  void readNewest(const Values&, std::uint64_t, NavState*) const override {}
};
}  // namespace

std::unique_ptr<DynamicsModel> makeDynamicsModel(const VioBackendOptions& options,
                                                 ResidualForceSource residual_force) {
  switch (options.method) {
    case VioMethod::kVio: return std::make_unique<NoDynamics>();
    case VioMethod::kVimo: return makeVimoDynamics(options);
    case VioMethod::kVid: return makeVidDynamics(options);
    case VioMethod::kHdvio: return makeHdvioDynamics(options, std::move(residual_force));
  }
  throw std::logic_error("makeDynamicsModel: unknown method");
}

}  // namespace hdvio
