#pragma once
// What the visual-inertial methods differ in: the dynamics model between two states. vio has
// none; vimo, vid and hdvio give every state an external force F(k) (a Key beside X, V, B),
// with a prior on the first one, and join consecutive states with their dynamics factor
// (dynamics_factors.h). VioBackend gets one from makeDynamicsModel at construction and asks it,
// so the method is chosen once (VioMethod only names it in the configuration).
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "hdvio/backend/vio_options.h"
#include "hdvio/core/factor_graph.h"
#include "hdvio/core/key.h"
#include "hdvio/core/nav_state.h"
#include "hdvio/core/sequence.h"
#include "hdvio/core/values.h"
#include "hdvio/factors/measurement_steps.h"

namespace hdvio {

// The pluggable residual-force provider of hdvio mode: given an interval and the current gyro
// bias estimate, the learned residual force (body frame, m/s^2) as a function of time over it.
// The learned module's providers are adapted to this shape by the pipeline library
// (backend/pipeline residual_force_adapter.h; the estimators do not depend on learned/).
using ResidualForceSource =
    std::function<ResidualForceFn(Timestamp t_i, Timestamp t_j, const Vec3& gyro_bias)>;

// The backend's measurement buffers (time-ordered), which the models preintegrate.
struct InertialBuffers {
  const std::vector<ImuSample>& imu;
  const std::vector<ThrustSample>& thrust;
};

// One interval [i, j] of the window: the estimate at i and the IMU's prediction at j.
struct StateInterval {
  std::uint64_t i = 0, j = 0;  // state indices
  Timestamp t_i = 0, t_j = 0;
  NavState state_i;
  Vec3 v_j = Vec3::Zero();  // predicted velocity at j (world frame)
  double dt = 0.0;          // the IMU preintegration's span
};

class DynamicsModel {
 public:
  virtual ~DynamicsModel() = default;

  // A frame is processed only once thrust covers its time (the force models preintegrate it).
  virtual bool needsThrust() const = 0;
  // The keys of state `index` beyond X, V, B: they are created and marginalized with it.
  virtual std::vector<Key> stateKeys(std::uint64_t index) const = 0;
  // The first state's extra values and their priors (s: the start, with its force guess).
  virtual void addFirstState(std::uint64_t index, const NavState& s, const InertialBuffers& in,
                             FactorGraph* priors, Values* values) const = 0;
  // The dynamics factor joining i and j (after j's IMU factor) and j's extra initial values.
  // Not const: a model may adapt its noise to what it has seen (hdvio's adaptive walk).
  virtual void addInterval(const StateInterval& interval, const InertialBuffers& in,
                           FactorGraph* graph, Values* values) = 0;
  // Reads the model's part of state `index` (its external force) from the estimate.
  virtual void readState(const Values& estimate, std::uint64_t index, NavState* s) const = 0;
  // The newest state as reported, given the one before it (`previous`).
  virtual void readNewest(const Values& estimate, std::uint64_t previous, NavState* s) const = 0;
};

// The model of options.method; residual_force is hdvio's learned force (null: zero).
std::unique_ptr<DynamicsModel> makeDynamicsModel(const VioBackendOptions& options,
                                                 ResidualForceSource residual_force = nullptr);

}  // namespace hdvio
