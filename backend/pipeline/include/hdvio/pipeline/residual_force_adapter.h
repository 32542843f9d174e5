#pragma once
// The learned residual-force provider (learned/residual_force_provider.h) in the shape the
// backend's dynamics preintegration asks for (ResidualForceSource, vio_backend.h), fed from the
// IMU and thrust an estimator has received so far; and the provider's force at a state, for
// the force outputs.
#include <memory>
#include <vector>

#include "hdvio/backend/vio_backend.h"
#include "hdvio/learned/residual_force_provider.h"

namespace hdvio {

// imu and thrust: the estimator's buffers (they grow; both must outlive the source). Over
// [t_i, t_j] the provider sees the thrust + gyro samples from t_i - historySeconds() to t_j.
ResidualForceSource residualForceSource(
    std::shared_ptr<const learned::ResidualForceProvider> provider,
    const std::vector<ImuSample>* imu, const std::vector<ThrustSample>* thrust);

// The provider's residual force (body frame) at s.t with the state's gyro-bias estimate, from
// the samples within 0.05 s around it (linear between them, as the dynamics preintegration
// uses it); zero when there are none.
Vec3 residualForceAtState(const learned::ResidualForceProvider& provider,
                          const std::vector<ImuSample>& imu,
                          const std::vector<ThrustSample>& thrust, const NavState& s);

}  // namespace hdvio
