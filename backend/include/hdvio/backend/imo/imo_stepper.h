#pragma once
// The one driver of the IMO error-state EKF (as OpenVINS separates its Propagator from its
// Updaters): it propagates the filter one IMU sample at a time and splits each IMU interval at
// the times its updaters ask for (inputs interpolated there), where they update the filter.
// The updaters (imo_updaters.h) are chosen once, at construction: the displacement update on
// the clone grid (imo, tlio, model_ekf), the displacements concatenated without filter
// updates (net_only), the gate-corner reprojections at camera frames (gate_io, optionally with
// the displacement update). The streaming estimator (backend/pipeline inertial_estimator.h)
// feeds it. docs/imo.md, docs/gate_io.md.
#include <limits>
#include <memory>
#include <vector>

#include "hdvio/backend/imo/imo_filter.h"
#include "hdvio/core/nav_state.h"
#include "hdvio/core/sequence.h"

namespace hdvio::imo {

constexpr Timestamp kNoUpdate = std::numeric_limits<Timestamp>::max();

struct ImoRunOptions {
  ImoFilterOptions filter;
  double update_rate_hz = 20.0;  // clones and displacement updates
  double window_s = 0.5;         // must be a whole number of update periods
  // Measurement covariance: the source's own, or diag(measurement_sigma^2) (the IMO release
  // uses a constant 0.01 m per axis).
  bool use_source_covariance = false;
  Vec3 measurement_sigma = Vec3::Constant(0.01);
  // Biases removed from the network window's IMU samples and from its gyro-integrated
  // rotations: false = the filter's current estimate; true = the initial biases (the IMO
  // release subtracts its fixed offline calibration there, the filter's estimate only in
  // propagation).
  bool initial_window_biases = false;
};

// Throws std::invalid_argument for inconsistent options (window not a multiple of the period).
void checkRunOptions(const ImoRunOptions& options);

// One displacement update of the filter (applied or gated out).
struct UpdateInnovation {
  Timestamp t = 0;  // the window's end (grid time)
  Innovation innovation;
  bool applied = true;
};

// The states and the counters of all updaters (each fills its own).
struct ImoRunOutput {
  // The initial state, then one per IMU sample (filters) or per grid time (net_only).
  std::vector<NavState> states;
  // Thread CPU time per stage; together the whole run. propagation = IMU steps and per-sample
  // output (the runner's total minus the rest), source = displacement source calls, update =
  // clone, displacement update, marginalization (net_only: concatenation), gate_update = gate
  // frames.
  double propagation_s = 0.0;
  double source_s = 0.0;
  double update_s = 0.0;
  double gate_update_s = 0.0;
  // Displacement windows.
  int updates = 0;
  int rejected = 0;        // by the chi-square gate
  int no_measurement = 0;  // source returned nothing
  std::vector<UpdateInnovation> innovations;  // filter updates only, one per update
  // Gate frames.
  int frames_applied = 0;
  int frames_rejected = 0;    // by the chi-square gate
  long corners_rejected = 0;  // by the per-corner gate
  long corners_used = 0;
  double mean_chi2_per_dof = 0.0;  // r' S^-1 r / (2 k) over all frames: ~1 for a consistent filter
};

// Something that corrects the filter (or reads it) at times of its own.
class ImoUpdater {
 public:
  virtual ~ImoUpdater() = default;
  // After the filter is initialized at the start state.
  virtual void start(ImoFilter& filter, ImoRunOutput& out) = 0;
  // After each propagation piece, with the gyro it was propagated with.
  virtual void propagated(const ImoFilter& filter, const Vec3& gyro, Timestamp t_from, Timestamp t_to) = 0;
  // When the updater next wants the filter (kNoUpdate: not now).
  virtual Timestamp nextTime() const = 0;
  // At nextTime(), the filter propagated exactly to it.
  virtual void update(ImoFilter& filter, ImoRunOutput& out) = 0;
  // The next time at which the displacement source is asked for a window (kNoUpdate: never).
  virtual Timestamp nextWindowEnd() const { return kNoUpdate; }
};

class ImoStepper {
 public:
  // first: the IMU sample at init.t; the filter starts from init's pose, velocity and biases
  // ([bg, ba]). Updaters at equal times act in the given order. imu_rate_states: keep the
  // filter's state after every IMU sample (false when an updater reports the states).
  ImoStepper(const ImoFilterOptions& filter, const NavState& init, const ImuSample& first,
             std::vector<std::unique_ptr<ImoUpdater>> updaters, bool imu_rate_states = true);
  ~ImoStepper();
  ImoStepper(const ImoStepper&) = delete;
  ImoStepper& operator=(const ImoStepper&) = delete;

  // The next sample, strictly after the previous one.
  void addImu(const ImuSample& sample);
  // The last sample stepped (init.t at the start).
  Timestamp time() const { return prev_.t; }
  // The next time an updater asks the displacement source for a window.
  Timestamp nextWindowEnd() const;
  NavState state() const;  // at the last sample (filters) or grid time (net_only)
  const ImoRunOutput& output() const { return out_; }
  ImoRunOutput& output() { return out_; }

 private:
  void step(const ImuSample& from, const ImuSample& to);

  ImoFilter filter_;
  std::vector<std::unique_ptr<ImoUpdater>> updaters_;
  const bool hold_;  // release propagation: the interval's newer sample (zero-order hold)
  const bool imu_rate_states_;
  ImuSample prev_;  // the last sample stepped
  ImoRunOutput out_;
};

}  // namespace hdvio::imo
