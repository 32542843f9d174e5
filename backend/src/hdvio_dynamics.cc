// hdvio's dynamics model: thrust plus the learned residual force and the drag law, with the
// external force a random walk from F_i to F_j (HdvioDynamicsFactor), optionally adapted to
// the accelerometer's evidence (adaptive_force_walk.h).
#include <algorithm>
#include <limits>
#include <optional>
#include <utility>

#include "force_dynamics.h"
#include "hdvio/backend/adaptive_force_walk.h"
#include "hdvio/factors/drag_model.h"
#include "hdvio/factors/dynamics_factors.h"

namespace hdvio {
using symbols::B;
using symbols::F;
using symbols::V;
using symbols::X;

namespace {
class HdvioDynamics final : public ForceDynamics {
 public:
  HdvioDynamics(const VioBackendOptions& options, ResidualForceSource residual_force)
      : ForceDynamics(options), residual_force_(std::move(residual_force)) {
    if (options.force_walk_adaptive.enabled)
      force_walk_.emplace(options.force_walk_adaptive, options.dynamics.force_random_walk,
                          options.imu.accel_noise_density);
  }

  void addInterval(const StateInterval& iv, const InertialBuffers& in, FactorGraph* graph,
                   Values* values) override {
    const NavState& s = iv.state_i;
    auto pit = preintegrate(iv, in, residualForce(iv.t_i, iv.t_j, s), values);
    DynamicsFactorParams params = intervalParams(iv);
    if (force_walk_) {
      // The interval's accelerometer-minus-model force (frame i mean, drag at the predicted
      // velocities), in the world frame.
      const Mat3 Ri = s.T_WB.R();
      const DragIntegral drag =
          integrateDrag(*pit, params.drag, params.sigma_velocity_i, params.sigma_velocity_j);
      const Vec3 f_W = Ri * (pit->correctedGamma(s.bias) - drag.beta) / iv.dt;
      params.force_random_walk = force_walk_->update(f_W, iv.dt);
    }
    // Outside what the model was trained on its measured error says nothing: the walk grows with
    // the distance beyond the envelope, to force_walk_outside_model at twice a bound.
    const double excess = modelEnvelopeExcess(iv, in);
    if (excess > 0.0)
      params.force_random_walk =
          std::max(params.force_random_walk, std::min(1.0, excess) * options().force_walk_outside_model);
    graph->add(std::make_shared<HdvioDynamicsFactor>(X(iv.i), V(iv.i), F(iv.i), X(iv.j), V(iv.j),
                                                     F(iv.j), B(iv.i), pit, params));
  }

  // F_j is joined to F_i by the walk, so the newest state's own force is the estimate.
  void readNewest(const Values&, std::uint64_t, NavState*) const override {}

 protected:
  // With init_force_window_s > 0 and the buffers covering it: as the adaptive walk's evidence,
  // accelerometer minus thrust, learned force and drag (at the state's velocity, held over the
  // span) in the frame at the window's start, rotated to the world.
  Vec3 firstForce(const NavState& s, const InertialBuffers& in) const override {
    const double window_s = options().init_force_window_s;
    const Timestamp from = s.t - fromSeconds(window_s);
    if (!(window_s > 0.0) || in.imu.empty() || in.thrust.empty() || in.imu.front().t > from ||
        in.thrust.front().t > from || in.imu.back().t < s.t || in.thrust.back().t < s.t)
      return s.f_ext_W;
    const PreintegratedThrust pit = PreintegratedThrust::integrate(
        in.imu, in.thrust, from, s.t, s.bias, options().thrust, residualForce(from, s.t, s));
    const Mat3 R_from = s.T_WB.R() * pit.deltaR().transpose();
    const Vec3 u = R_from.transpose() * s.v_W;
    const DragIntegral drag = integrateDrag(pit, options().dynamics.drag, u, u);
    const Vec3 f_W = R_from * (pit.correctedGamma(s.bias) - drag.beta) / pit.dt();
    return f_W.allFinite() ? f_W : s.f_ext_W;
  }

 private:
  // How far the interval leaves where the model was trained (ModelEnvelope::excess, 0 inside):
  // speed at both ends (the estimate at i, the IMU's prediction at j), every gyro and thrust
  // sample inside it.
  double modelEnvelopeExcess(const StateInterval& iv, const InertialBuffers& in) const {
    const ModelEnvelope& e = options().model_envelope;
    if (e.unbounded()) return 0.0;
    const double speed = std::max(iv.state_i.v_W.norm(), iv.v_j.norm());
    double rate = 0.0;
    const Vec3 gyro_bias = iv.state_i.bias.head<3>();
    for (auto it = std::lower_bound(in.imu.begin(), in.imu.end(), iv.t_i,
                                    [](const ImuSample& s, Timestamp t) { return s.t < t; });
         it != in.imu.end() && it->t <= iv.t_j; ++it)
      rate = std::max(rate, (it->gyro - gyro_bias).norm());
    double thrust_lo = std::numeric_limits<double>::infinity(), thrust_hi = 0.0;
    for (auto it = std::lower_bound(in.thrust.begin(), in.thrust.end(), iv.t_i,
                                    [](const ThrustSample& s, Timestamp t) { return s.t < t; });
         it != in.thrust.end() && it->t <= iv.t_j; ++it) {
      thrust_lo = std::min(thrust_lo, it->thrust.norm());
      thrust_hi = std::max(thrust_hi, it->thrust.norm());
    }
    if (thrust_hi < thrust_lo) thrust_lo = thrust_hi = e.thrust_min;  // no sample inside
    return std::max(e.excess(speed, rate, thrust_lo), e.excess(speed, rate, thrust_hi));
  }

  // The learned force over [t_i, t_j] at the gyro bias of s; zero without a provider.
  ResidualForceFn residualForce(Timestamp t_i, Timestamp t_j, const NavState& s) const {
    return residual_force_ ? residual_force_(t_i, t_j, s.bias.head<3>()) : ResidualForceFn();
  }

  ResidualForceSource residual_force_;
  std::optional<AdaptiveForceWalk> force_walk_;  // backend.force_walk_adaptive
};
}  // namespace

std::unique_ptr<DynamicsModel> makeHdvioDynamics(const VioBackendOptions& options,
                                                 ResidualForceSource residual_force) {
  return std::make_unique<HdvioDynamics>(options, std::move(residual_force));
}

}  // namespace hdvio
