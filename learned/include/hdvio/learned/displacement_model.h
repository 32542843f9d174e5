#pragma once
// The learned displacement network of IMO (Cioffi et al., RA-L 2023) and its TLIO-style
// IMU-only baseline: a residual TCN maps 0.5 s of [thrust or accelerometer; gyroscope], both
// rotated to the world frame, to the world-frame displacement over that window. The IMO
// filter (backend/) clones states at the window ends and uses the prediction as a
// relative-position measurement with covariance `covariance`. docs/imo_network.md.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "hdvio/core/sequence.h"
#include "hdvio/core/time.h"
#include "hdvio/learned/tcn.h"

namespace hdvio::learned {

enum class DisplacementInputKind { kThrustGyro, kAccelGyro };  // IMO / TLIO-style

// Where the N samples of the window [t_begin, t_end] sit (the convention the network was trained
// with): kEnd (hdvio's networks) at t_end - (N-1-k) / rate, so sample k stands for
// (t_k - 1/rate, t_k]; kBegin (the IMO reference release) at t_begin + k / rate, so the last
// sample is 1/rate before t_end.
enum class DisplacementSampleTimes { kEnd, kBegin };

struct DisplacementPrediction {
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  // world frame, m, p(t_end) - p(t_end - window)
  // m^2 (fixed from validation error, or a variance head); zero when the model has none.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// "thrust_gyro" / "accel_gyro" (the spelling of weight files and configs).
std::string toString(DisplacementInputKind kind);
// Throws std::invalid_argument on anything else.
DisplacementInputKind displacementInputKindFromString(const std::string& name);

class DisplacementModel {
 public:
  // sigma: per-axis standard deviation of the displacement error (m), used as the diagonal
  // covariance when the network has no variance head; nullopt: no covariance (the IMO
  // release's network; the filter then needs its own measurement sigma). Throws
  // std::invalid_argument if the network is not a displacement network (6 inputs, 3 outputs)
  // or sigma is not positive.
  DisplacementModel(Tcn tcn, DisplacementInputKind kind, std::optional<Eigen::Vector3d> sigma,
                    DisplacementSampleTimes sample_times = DisplacementSampleTimes::kEnd);

  static DisplacementModel load(const std::string& path);  // throws InputError naming file and line

  DisplacementInputKind inputKind() const { return kind_; }
  double sampleRateHz() const { return tcn_.architecture().sample_rate_hz; }     // 100
  int windowSamples() const { return tcn_.architecture().window; }               // 50
  double windowSeconds() const { return windowSamples() / sampleRateHz(); }      // 0.5
  Timestamp windowDuration() const { return fromSeconds(windowSeconds()); }
  bool hasCovariance() const { return sigma_.has_value() || tcn_.architecture().variance_head; }
  const std::optional<Eigen::Vector3d>& sigma() const { return sigma_; }
  DisplacementSampleTimes sampleTimes() const { return sample_times_; }
  const Tcn& tcn() const { return tcn_; }

  // window: 6 x windowSamples(), rows [thrust-or-accel xyz; gyro xyz] rotated to the world
  // frame, oldest first. Throws std::invalid_argument on a wrong shape. `workspace`: the
  // network's scratch (Tcn::predictWindow); without it the call allocates its own.
  DisplacementPrediction predict(const MatrixXf& window, TcnWorkspace* workspace) const;
  DisplacementPrediction predict(const MatrixXf& window) const;

 private:
  Tcn tcn_;
  DisplacementInputKind kind_;
  std::optional<Eigen::Vector3d> sigma_;
  DisplacementSampleTimes sample_times_;
};

// Time of sample k (0 = oldest) of the window ending at t_end (model.sampleTimes()):
// kEnd: t_end - (N - 1 - k) / rate; kBegin: t_end - windowSeconds() + k / rate. Either way the
// samples lie in the window [t_end - windowSeconds(), t_end] whose displacement is predicted.
Timestamp displacementSampleTime(const DisplacementModel& model, Timestamp t_end, int k);

// World-frame input window ending at t_end: samples at the model's rate (linear interpolation of the IMU and
// thrust streams), gyro (and accel) bias subtracted, each sample rotated by world_from_body(t) of that sample.
// Throws InputError if the streams do not cover [t_end - window, t_end].
MatrixXf makeDisplacementWindow(const DisplacementModel& model, const std::vector<ImuSample>& imu,
                                const std::vector<ThrustSample>& thrust, Timestamp t_end,
                                const std::function<Eigen::Quaterniond(Timestamp)>& world_from_body,
                                const Eigen::Vector3d& gyro_bias, const Eigen::Vector3d& accel_bias);

}  // namespace hdvio::learned
