#pragma once
// Drives the IMO filter over an IMU stream (as the IMO / TLIO releases do): propagate at IMU
// rate, clone the state on a fixed grid at the update rate (partial propagation to the exact
// grid time), and once the clones span one window, ask the displacement source for the
// displacement between the window's first and last clone, update, and marginalize every clone
// up to the window's start (so at most window * rate clones stay). Also the network-only
// baseline: displacements concatenated without a filter. docs/imo.md.
#include <functional>
#include <memory>
#include <vector>

#include "hdvio/backend/imo/displacement_source.h"
#include "hdvio/backend/imo/imo_filter.h"
#include "hdvio/core/nav_state.h"

namespace hdvio::imo {

struct ImoRunOptions {
  ImoFilterOptions filter;
  double update_rate_hz = 20.0;  // clones and updates
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

// One displacement update of the filter (applied or gated out).
struct UpdateInnovation {
  Timestamp t = 0;  // the window's end (grid time)
  Innovation innovation;
  bool applied = true;
};

struct ImoRunOutput {
  std::vector<NavState> states;  // one per IMU sample after the first (filter), per update (net only)
  // Thread CPU time per stage; together the whole run. propagation = IMU steps and per-sample
  // output, source = displacement source calls, update = clone, update, marginalization.
  double propagation_s = 0.0;
  double source_s = 0.0;
  double update_s = 0.0;
  int updates = 0;
  int rejected = 0;      // by the chi-square gate
  int no_measurement = 0;  // source returned nothing
  std::vector<UpdateInnovation> innovations;  // filter only, one per update
};

// Throws std::invalid_argument for inconsistent options (window not a multiple of the period).
void checkRunOptions(const ImoRunOptions& options);

// The filter (or the network-only baseline) one IMU sample at a time, as runImoFilter and
// runNetworkOnly below do over a whole stream: propagation at IMU rate, the update grid
// (start + k / update_rate_hz) split into the IMU intervals. The streaming estimators
// (backend/pipeline inertial_estimator.h) feed it; it keeps the output states.
class ImoStepper {
 public:
  enum class Mode { kFilter, kNetworkOnly };
  // first: the IMU sample at init.t. The source is asked for one window at each grid time.
  ImoStepper(Mode mode, const ImoRunOptions& options, const NavState& init, const ImuSample& first,
             DisplacementSource source);
  ~ImoStepper();
  ImoStepper(const ImoStepper&) = delete;
  ImoStepper& operator=(const ImoStepper&) = delete;

  // The next sample, strictly after the previous one.
  void addImu(const ImuSample& sample);
  // The next grid time: a sample at or after it asks the source for a window ending there.
  Timestamp nextGridTime() const;
  NavState state() const;  // at the last sample (filter) or grid time (network only)
  // The states and counters so far. Stage times: source_s and the grid time (clone, source,
  // update, marginalization) in gridSeconds(); the caller owns the propagation time.
  const ImoRunOutput& output() const;
  ImoRunOutput& output();
  double gridSeconds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The filter starts at init.t (must be an IMU sample time) from init's pose, velocity and
// biases ([bg, ba]). on_progress (may be empty) gets the time after each IMU sample.
ImoRunOutput runImoFilter(const std::vector<ImuSample>& imu, const NavState& init,
                          const ImoRunOptions& options, const DisplacementSource& source,
                          const std::function<void(Timestamp)>& on_progress = {});

// Network only: orientation by gyro integration from init (biases fixed at init's), positions
// p(t) = p(t - window) + displacement(t) on the update grid; the first window's positions
// come from IMU dead reckoning from init. Velocity reported = displacement / window.
ImoRunOutput runNetworkOnly(const std::vector<ImuSample>& imu, const NavState& init,
                            const ImoRunOptions& options, const DisplacementSource& source,
                            const std::function<void(Timestamp)>& on_progress = {});

}  // namespace hdvio::imo
