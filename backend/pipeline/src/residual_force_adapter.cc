#include "hdvio/pipeline/residual_force_adapter.h"

#include <utility>

namespace hdvio {

ResidualForceSource residualForceSource(
    std::shared_ptr<const learned::ResidualForceProvider> provider,
    const std::vector<ImuSample>* imu, const std::vector<ThrustSample>* thrust) {
  if (!provider) return nullptr;
  return [provider = std::move(provider), imu, thrust](Timestamp t_i, Timestamp t_j,
                                                       const Vec3& gyro_bias) {
    const Timestamp from = t_i - fromSeconds(provider->historySeconds());
    const auto inputs = learned::makeDynamicsInputs(*imu, *thrust, from, t_j);
    auto forces = std::make_shared<const std::vector<learned::ResidualForce>>(
        provider->residualForces(inputs, t_i, t_j, gyro_bias));
    return ResidualForceFn([forces](Timestamp t) { return learned::residualForceAt(*forces, t); });
  };
}

Vec3 residualForceAtState(const learned::ResidualForceProvider& provider,
                          const std::vector<ImuSample>& imu,
                          const std::vector<ThrustSample>& thrust, const NavState& s) {
  const Timestamp margin = fromSeconds(0.05);  // thrust samples on both sides at >= 20 Hz
  const Timestamp from = s.t - margin - fromSeconds(provider.historySeconds());
  const auto inputs = learned::makeDynamicsInputs(imu, thrust, from, s.t + margin);
  const auto forces = provider.residualForces(inputs, s.t - margin, s.t + margin, s.bias.head<3>());
  return forces.empty() ? Vec3::Zero() : learned::residualForceAt(forces, s.t);
}

}  // namespace hdvio
