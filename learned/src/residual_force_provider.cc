#include "hdvio/learned/residual_force_provider.h"

#include <algorithm>
#include <stdexcept>

#include "hdvio/core/error.h"

namespace hdvio::learned {
namespace {

// Indices of the samples with t_i <= t <= t_j, after checking the arguments.
std::pair<std::size_t, std::size_t> samplesInInterval(const std::vector<DynamicsInput>& samples,
                                                      Timestamp t_i, Timestamp t_j) {
  if (t_i > t_j) throw std::invalid_argument("residual force interval has t_i > t_j");
  for (std::size_t k = 1; k < samples.size(); ++k) {
    if (samples[k].t <= samples[k - 1].t) {
      throw std::invalid_argument("thrust/gyro samples are not strictly increasing in time");
    }
  }
  std::size_t first = 0;
  while (first < samples.size() && samples[first].t < t_i) ++first;
  std::size_t last = first;
  while (last < samples.size() && samples[last].t <= t_j) ++last;
  return {first, last};
}

// One residual force per sample with t_i <= t <= t_j: force_of(sample) for each.
template <typename ForceOf>
std::vector<ResidualForce> forcesInInterval(const std::vector<DynamicsInput>& samples,
                                            Timestamp t_i, Timestamp t_j, ForceOf force_of) {
  const auto [first, last] = samplesInInterval(samples, t_i, t_j);
  std::vector<ResidualForce> out;
  out.reserve(last - first);
  for (std::size_t k = first; k < last; ++k) out.push_back(force_of(samples[k]));
  return out;
}

}  // namespace

std::vector<ResidualForce> ZeroResidualForceProvider::residualForces(
    const std::vector<DynamicsInput>& samples, Timestamp t_i, Timestamp t_j,
    const Vec3& /*gyro_bias*/) const {
  return forcesInInterval(samples, t_i, t_j, [](const DynamicsInput& s) {
    return ResidualForce{s.t, Vec3::Zero(), Mat3::Zero()};
  });
}

TcnResidualForceProvider::TcnResidualForceProvider(std::shared_ptr<const ResidualForceModel> model)
    : model_(std::move(model)) {
  if (!model_) throw std::invalid_argument("TcnResidualForceProvider needs a model");
}

std::vector<ResidualForce> TcnResidualForceProvider::residualForces(
    const std::vector<DynamicsInput>& samples, Timestamp t_i, Timestamp t_j,
    const Vec3& gyro_bias) const {
  return forcesInInterval(samples, t_i, t_j, [&](const DynamicsInput& s) {
    const ResidualForcePrediction p = model_->predict(model_->windowEndingAt(samples, s.t, gyro_bias));
    return ResidualForce{s.t, p.force, p.covariance};
  });
}

GroundTruthResidualForceProvider::GroundTruthResidualForceProvider(std::vector<ForceSample> forces)
    : forces_(std::move(forces)) {
  if (forces_.empty()) throw std::invalid_argument("no ground-truth forces");
  for (std::size_t k = 1; k < forces_.size(); ++k)
    if (forces_[k].t <= forces_[k - 1].t)
      throw std::invalid_argument("ground-truth forces are not strictly increasing in time");
}

std::vector<ResidualForce> GroundTruthResidualForceProvider::residualForces(
    const std::vector<DynamicsInput>& samples, Timestamp t_i, Timestamp t_j,
    const Vec3& /*gyro_bias*/) const {
  return forcesInInterval(samples, t_i, t_j, [this](const DynamicsInput& s) {
    const auto hi = std::lower_bound(forces_.begin(), forces_.end(), s.t,
                                     [](const ForceSample& f, Timestamp v) { return f.t < v; });
    Vec3 drag;
    if (hi == forces_.begin()) {
      drag = hi->drag;
    } else if (hi == forces_.end()) {
      drag = forces_.back().drag;
    } else {
      const auto lo = hi - 1;
      const double a = static_cast<double>(s.t - lo->t) / static_cast<double>(hi->t - lo->t);
      drag = (1.0 - a) * lo->drag + a * hi->drag;
    }
    return ResidualForce{s.t, drag, Mat3::Zero()};
  });
}

std::vector<DynamicsInput> makeDynamicsInputs(const std::vector<ImuSample>& imu,
                                              const std::vector<ThrustSample>& thrust,
                                              Timestamp t_from, Timestamp t_to) {
  std::vector<DynamicsInput> out;
  if (imu.empty()) return out;
  for (const ThrustSample& s : thrust) {
    if (s.t < t_from || s.t > t_to || s.t < imu.front().t || s.t > imu.back().t) continue;
    const auto hi = std::lower_bound(imu.begin(), imu.end(), s.t,
                                     [](const ImuSample& m, Timestamp v) { return m.t < v; });
    Vec3 gyro = hi->gyro;
    if (hi->t != s.t) {
      const auto lo = hi - 1;
      const double a = static_cast<double>(s.t - lo->t) / static_cast<double>(hi->t - lo->t);
      gyro = (1.0 - a) * lo->gyro + a * hi->gyro;
    }
    out.push_back({s.t, s.thrust, gyro});
  }
  return out;
}

Vec3 residualForceAt(const std::vector<ResidualForce>& forces, Timestamp t) {
  if (forces.empty()) throw std::invalid_argument("no residual forces to interpolate");
  if (t <= forces.front().t) return forces.front().force;
  if (t >= forces.back().t) return forces.back().force;
  const auto hi = std::lower_bound(forces.begin(), forces.end(), t,
                                   [](const ResidualForce& f, Timestamp v) { return f.t < v; });
  const auto lo = hi - 1;
  const double a = static_cast<double>(t - lo->t) / static_cast<double>(hi->t - lo->t);
  return (1.0 - a) * lo->force + a * hi->force;
}

std::unique_ptr<ResidualForceProvider> makeResidualForceProvider(const ConfigReader& section,
                                                                 const std::string& base_dir) {
  std::string type;
  section.readChoice("type", &type, {"zero", "tcn"}, true);
  if (type == "zero") {
    section.finish();
    return std::make_unique<ZeroResidualForceProvider>();
  }
  std::string weights;
  section.read("weights", &weights);
  double sigma = 0.3;
  section.readInRange("default_sigma", &sigma, 0.0, 100.0);
  section.finish();
  if (!base_dir.empty() && !weights.empty() && weights[0] != '/') weights = base_dir + "/" + weights;
  return std::make_unique<TcnResidualForceProvider>(ResidualForceModel::load(weights, sigma));
}

}  // namespace hdvio::learned
