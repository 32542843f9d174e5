#pragma once
// The learned residual force: a TCN maps a short buffer of collective thrust and
// bias-corrected gyroscope to the force the thrust model misses (drag, rotor effects), as a
// mass-normalized body-frame vector (m/s^2), plus its covariance.
#include <memory>
#include <string>
#include <vector>

#include "hdvio/core/drag_law.h"
#include "hdvio/core/lie.h"
#include "hdvio/core/model_envelope.h"
#include "hdvio/core/time.h"
#include "hdvio/learned/tcn.h"

namespace hdvio::learned {

// One input sample: mass-normalized collective thrust and gyroscope, both in the body (IMU)
// frame. The gyroscope is raw; the bias is subtracted where the model is evaluated.
struct DynamicsInput {
  Timestamp t = 0;
  Vec3 thrust = Vec3::Zero();  // m/s^2
  Vec3 gyro = Vec3::Zero();    // rad/s
};

struct ResidualForcePrediction {
  Vec3 force = Vec3::Zero();           // m/s^2, body frame
  Mat3 covariance = Mat3::Zero();      // (m/s^2)^2
};

class ResidualForceModel {
 public:
  // Without a variance head, every prediction gets covariance default_sigma^2 * I. drag_law:
  // the law the network was trained to complement (weight file version 3), none by default.
  ResidualForceModel(Tcn tcn, double default_sigma, DragLaw drag_law = {}, double force_walk = 0.0,
                     ModelEnvelope envelope = {});
  // Loads a weight file (tcn_weight_file.h); throws InputError on a bad file.
  static std::shared_ptr<const ResidualForceModel> load(const std::string& path,
                                                        double default_sigma);

  const Tcn& tcn() const { return tcn_; }
  // The dynamics must add this law at the state's velocity (hybrid model); zero if none.
  const DragLaw& dragLaw() const { return drag_law_; }
  // Random walk (m/s^2/sqrt(s)) of the model's error on held-out flights (force_model_error.h):
  // the least the estimator's external-force walk may be; 0 when the file does not say.
  double forceWalk() const { return force_walk_; }
  // What its training samples held (weight file version 7); unbounded when the file does not say.
  const ModelEnvelope& envelope() const { return envelope_; }
  int window() const { return tcn_.architecture().window; }
  double sampleRateHz() const { return tcn_.architecture().sample_rate_hz; }
  double windowSeconds() const { return (window() - 1) / sampleRateHz(); }

  // window: exactly window() samples at sampleRateHz(), oldest first, gyro bias already
  // removed. Throws std::invalid_argument on a wrong length.
  ResidualForcePrediction predict(const std::vector<DynamicsInput>& window) const;

  // The window ending at t_end, interpolated linearly from time-ordered samples of any rate
  // (thrust and gyro), with gyro_bias subtracted. Before the first sample the first sample
  // is held (start of a flight). Throws std::invalid_argument if samples is empty or t_end
  // lies after the last sample.
  std::vector<DynamicsInput> windowEndingAt(const std::vector<DynamicsInput>& samples,
                                            Timestamp t_end, const Vec3& gyro_bias) const;

 private:
  Tcn tcn_;
  double default_sigma_;
  DragLaw drag_law_;
  double force_walk_ = 0.0;
  ModelEnvelope envelope_;
};

// Time-ordered interpolation used by windowEndingAt (exposed for tests and tools).
DynamicsInput interpolateInput(const std::vector<DynamicsInput>& samples, Timestamp t);

}  // namespace hdvio::learned
