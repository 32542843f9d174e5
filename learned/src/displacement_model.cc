#include "hdvio/learned/displacement_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hdvio/core/error.h"
#include "hdvio/learned/tcn_weight_file.h"

namespace hdvio::learned {
namespace {

// Linear interpolation in a time-ordered stream; `hint` walks forward because the window's
// sample times increase. Requires stream.front().t <= t <= stream.back().t.
template <typename Sample, typename Get>
Eigen::Vector3d interpolate(const std::vector<Sample>& stream, Timestamp t, std::size_t* hint,
                            Get get) {
  std::size_t i = *hint;
  while (i + 1 < stream.size() && stream[i + 1].t < t) ++i;
  *hint = i;
  if (i + 1 >= stream.size() || stream[i].t >= t) return get(stream[i]);
  const Sample& a = stream[i];
  const Sample& b = stream[i + 1];
  const double span = static_cast<double>(b.t - a.t);
  const double w = span > 0.0 ? static_cast<double>(t - a.t) / span : 1.0;
  return (1.0 - w) * get(a) + w * get(b);
}

template <typename Sample>
void requireCoverage(const std::vector<Sample>& stream, const std::string& what, Timestamp begin,
                     Timestamp end) {
  if (stream.empty()) throw InputError("", 0, "no " + what + " samples for the displacement window");
  if (stream.front().t > begin || stream.back().t < end) {
    throw InputError("", 0,
                     what + " samples [" + std::to_string(toSeconds(stream.front().t)) + ", " +
                         std::to_string(toSeconds(stream.back().t)) +
                         "] s do not cover the displacement window [" +
                         std::to_string(toSeconds(begin)) + ", " + std::to_string(toSeconds(end)) +
                         "] s");
  }
}

}  // namespace

std::string toString(DisplacementInputKind kind) {
  return kind == DisplacementInputKind::kThrustGyro ? "thrust_gyro" : "accel_gyro";
}

DisplacementInputKind displacementInputKindFromString(const std::string& name) {
  if (name == "thrust_gyro") return DisplacementInputKind::kThrustGyro;
  if (name == "accel_gyro") return DisplacementInputKind::kAccelGyro;
  throw std::invalid_argument("unknown displacement input kind '" + name +
                              "' (expected thrust_gyro or accel_gyro)");
}

DisplacementModel::DisplacementModel(Tcn tcn, DisplacementInputKind kind,
                                     std::optional<Eigen::Vector3d> sigma,
                                     DisplacementSampleTimes sample_times)
    : tcn_(std::move(tcn)), kind_(kind), sigma_(std::move(sigma)), sample_times_(sample_times) {
  if (tcn_.architecture().input_channels != 6) {
    throw std::invalid_argument("a displacement network needs 6 input channels, found " +
                                std::to_string(tcn_.architecture().input_channels));
  }
  if (sigma_ && (!(sigma_->array() > 0.0).all() || !sigma_->allFinite())) {
    throw std::invalid_argument("displacement sigma must be positive");
  }
}

DisplacementModel DisplacementModel::load(const std::string& path) {
  TcnFile file = loadTcnFile(path);
  if (file.info.task != "displacement") {
    throw InputError(path, 0, "not a displacement network (task '" + file.info.task +
                                  "'; expected a version-2 file with \"task displacement\")");
  }
  std::optional<Eigen::Vector3d> sigma;  // "output_sigma none": no covariance
  if (file.info.output_sigma.size() == 3)
    sigma = Eigen::Vector3d(file.info.output_sigma[0], file.info.output_sigma[1], file.info.output_sigma[2]);
  const DisplacementSampleTimes times =
      file.info.sample_times == "begin" ? DisplacementSampleTimes::kBegin : DisplacementSampleTimes::kEnd;
  try {
    return DisplacementModel(std::move(file.tcn), displacementInputKindFromString(file.info.inputs),
                             sigma, times);
  } catch (const std::invalid_argument& e) {
    throw InputError(path, 0, e.what());
  }
}

DisplacementPrediction DisplacementModel::predict(const MatrixXf& window) const {
  TcnWorkspace workspace;
  return predict(window, &workspace);
}

DisplacementPrediction DisplacementModel::predict(const MatrixXf& window, TcnWorkspace* workspace) const {
  const TcnOutput out = tcn_.predictWindow(window, workspace);
  DisplacementPrediction p;
  p.displacement = out.force.cast<double>();
  if (tcn_.architecture().variance_head) {
    p.covariance = out.log_variance.cast<double>().array().exp().matrix().asDiagonal();
  } else if (sigma_) {
    p.covariance = sigma_->array().square().matrix().asDiagonal();
  }
  return p;
}

Timestamp displacementSampleTime(const DisplacementModel& model, Timestamp t_end, int k) {
  if (model.sampleTimes() == DisplacementSampleTimes::kBegin)
    return t_end - model.windowDuration() + fromSeconds(k / model.sampleRateHz());
  const int n = model.windowSamples();
  return t_end - fromSeconds((n - 1 - k) / model.sampleRateHz());
}

MatrixXf makeDisplacementWindow(const DisplacementModel& model, const std::vector<ImuSample>& imu,
                                const std::vector<ThrustSample>& thrust, Timestamp t_end,
                                const std::function<Eigen::Quaterniond(Timestamp)>& world_from_body,
                                const Eigen::Vector3d& gyro_bias, const Eigen::Vector3d& accel_bias) {
  const bool use_thrust = model.inputKind() == DisplacementInputKind::kThrustGyro;
  const Timestamp begin = t_end - model.windowDuration();
  requireCoverage(imu, "IMU", begin, t_end);
  if (use_thrust) requireCoverage(thrust, "thrust", begin, t_end);

  const int n = model.windowSamples();
  MatrixXf window(6, n);
  // Start the forward walks at the window's first sample (binary search, streams are long).
  auto firstBefore = [begin](const auto& stream) {
    const auto it = std::lower_bound(stream.begin(), stream.end(), begin,
                                     [](const auto& s, Timestamp t) { return s.t < t; });
    return static_cast<std::size_t>(std::max<long>(0, (it - stream.begin()) - 1));
  };
  std::size_t imu_hint = firstBefore(imu), thrust_hint = use_thrust ? firstBefore(thrust) : 0;
  for (int k = 0; k < n; ++k) {
    const Timestamp t = displacementSampleTime(model, t_end, k);
    const Eigen::Matrix3d R = world_from_body(t).normalized().toRotationMatrix();
    const Eigen::Vector3d gyro =
        interpolate(imu, t, &imu_hint, [](const ImuSample& s) { return s.gyro; }) - gyro_bias;
    Eigen::Vector3d force;
    if (use_thrust) {
      force = interpolate(thrust, t, &thrust_hint, [](const ThrustSample& s) { return s.thrust; });
    } else {
      std::size_t accel_hint = imu_hint;  // same stream, same position
      force = interpolate(imu, t, &accel_hint, [](const ImuSample& s) { return s.accel; }) - accel_bias;
    }
    window.block<3, 1>(0, k) = (R * force).cast<float>();
    window.block<3, 1>(3, k) = (R * gyro).cast<float>();
  }
  return window;
}

}  // namespace hdvio::learned
