#include "hdvio/learned/residual_force_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hdvio/core/error.h"
#include "hdvio/learned/tcn_weight_file.h"

namespace hdvio::learned {

ResidualForceModel::ResidualForceModel(Tcn tcn, double default_sigma, DragLaw drag_law, double force_walk,
                                       ModelEnvelope envelope)
    : tcn_(std::move(tcn)),
      default_sigma_(default_sigma),
      drag_law_(std::move(drag_law)),
      force_walk_(force_walk),
      envelope_(envelope) {
  if (!(default_sigma >= 0.0) || !std::isfinite(default_sigma)) {
    throw std::invalid_argument("default_sigma must be finite and non-negative");
  }
  if (tcn_.architecture().input_channels != 6) {
    throw std::invalid_argument("a residual force TCN takes 6 input channels (thrust, gyro)");
  }
}

std::shared_ptr<const ResidualForceModel> ResidualForceModel::load(const std::string& path,
                                                                   double default_sigma) {
  TcnFile file = loadTcnFile(path);
  if (file.info.task != "force") {
    throw InputError(path, 0, "not a residual-force network (task '" + file.info.task + "')");
  }
  return std::make_shared<const ResidualForceModel>(std::move(file.tcn), default_sigma,
                                                    file.info.drag_law, file.info.force_walk,
                                                    file.info.envelope);
}

ResidualForcePrediction ResidualForceModel::predict(const std::vector<DynamicsInput>& window) const {
  if (static_cast<int>(window.size()) != this->window()) {
    throw std::invalid_argument("residual force window has " + std::to_string(window.size()) +
                                " samples, expected " + std::to_string(this->window()));
  }
  MatrixXf x(6, this->window());
  for (int k = 0; k < this->window(); ++k) {
    x.col(k).head<3>() = window[k].thrust.cast<float>();
    x.col(k).tail<3>() = window[k].gyro.cast<float>();
  }
  const TcnOutput out = tcn_.predictWindow(x);
  ResidualForcePrediction p;
  p.force = out.force.cast<double>();
  if (tcn_.architecture().variance_head) {
    // Clamp the log-variance so a wild output cannot make the factor infinitely stiff or weak.
    const Eigen::Array3d logvar = out.log_variance.cast<double>().array().min(10.0).max(-20.0);
    p.covariance = logvar.exp().matrix().asDiagonal();
  } else {
    p.covariance = default_sigma_ * default_sigma_ * Mat3::Identity();
  }
  return p;
}

DynamicsInput interpolateInput(const std::vector<DynamicsInput>& samples, Timestamp t) {
  if (samples.empty()) throw std::invalid_argument("no thrust/gyro samples to interpolate");
  if (t <= samples.front().t) {
    DynamicsInput s = samples.front();
    s.t = t;
    return s;
  }
  if (t > samples.back().t) {
    throw std::invalid_argument("time " + std::to_string(t) + " ns is after the last sample");
  }
  const auto hi = std::lower_bound(samples.begin(), samples.end(), t,
                                   [](const DynamicsInput& s, Timestamp v) { return s.t < v; });
  if (hi->t == t) return *hi;
  const auto lo = hi - 1;
  const double a = static_cast<double>(t - lo->t) / static_cast<double>(hi->t - lo->t);
  DynamicsInput s;
  s.t = t;
  s.thrust = (1.0 - a) * lo->thrust + a * hi->thrust;
  s.gyro = (1.0 - a) * lo->gyro + a * hi->gyro;
  return s;
}

std::vector<DynamicsInput> ResidualForceModel::windowEndingAt(
    const std::vector<DynamicsInput>& samples, Timestamp t_end, const Vec3& gyro_bias) const {
  std::vector<DynamicsInput> w(window());
  const double dt_ns = 1e9 / sampleRateHz();
  for (int k = 0; k < window(); ++k) {
    const Timestamp t = t_end - static_cast<Timestamp>(std::llround((window() - 1 - k) * dt_ns));
    w[k] = interpolateInput(samples, t);
    w[k].gyro -= gyro_bias;
  }
  return w;
}

}  // namespace hdvio::learned
