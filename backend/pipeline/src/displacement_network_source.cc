#include "hdvio/pipeline/displacement_network_source.h"

#include <algorithm>
#include <utility>

namespace hdvio {
namespace {

// The sample at time t (if any, and not the last) takes the next sample's values.
template <class Sample>
void repeatNextSample(std::vector<Sample>* stream, Timestamp t) {
  auto it = std::lower_bound(stream->begin(), stream->end(), t,
                             [](const Sample& s, Timestamp tt) { return s.t < tt; });
  if (it == stream->end() || it->t != t || it + 1 == stream->end()) return;
  *it = *(it + 1);
  it->t = t;
}

}  // namespace

imo::DisplacementSource networkDisplacementSource(
    std::shared_ptr<const learned::DisplacementEnsemble> networks,
    std::shared_ptr<const std::vector<ImuSample>> imu,
    std::shared_ptr<const std::vector<ThrustSample>> thrust, std::optional<Timestamp> repeat_next_at) {
  const bool use_thrust = networks->inputKind() == learned::DisplacementInputKind::kThrustGyro;
  const Timestamp w = networks->windowDuration();
  auto covered = [w](const auto& stream, Timestamp t_end) {
    return !stream.empty() && stream.front().t <= t_end - w && stream.back().t >= t_end;
  };
  // The network's scratch is part of the source: each copy of the std::function has its own.
  return [networks = std::move(networks), imu = std::move(imu), thrust = std::move(thrust), use_thrust, covered, w,
          repeat_next_at, workspace = learned::TcnWorkspace()](
             const imo::DisplacementRequest& r) mutable -> std::optional<imo::DisplacementEstimate> {
    if (!covered(*imu, r.t_end) || (use_thrust && !covered(*thrust, r.t_end))) return std::nullopt;
    learned::MatrixXf window;
    if (repeat_next_at && r.t_end - 2 * w <= *repeat_next_at) {
      // Only the first windows can reach the repeated sample: those read copies.
      std::vector<ImuSample> imu_copy = *imu;
      std::vector<ThrustSample> thrust_copy = *thrust;
      repeatNextSample(&imu_copy, *repeat_next_at);
      repeatNextSample(&thrust_copy, *repeat_next_at);
      window = learned::makeDisplacementWindow(networks->layout(), imu_copy, thrust_copy, r.t_end, r.world_from_body,
                                               r.gyro_bias, r.accel_bias);
    } else {
      window = learned::makeDisplacementWindow(networks->layout(), *imu, *thrust, r.t_end, r.world_from_body, r.gyro_bias,
                                               r.accel_bias);
    }
    const learned::DisplacementPrediction p = networks->predict(window, &workspace);
    imo::DisplacementEstimate e;
    e.z = p.displacement;
    e.covariance = p.covariance;
    return e;
  };
}

imo::DisplacementSource networkDisplacementSource(
    std::shared_ptr<const learned::DisplacementModel> model,
    std::shared_ptr<const std::vector<ImuSample>> imu,
    std::shared_ptr<const std::vector<ThrustSample>> thrust, std::optional<Timestamp> repeat_next_at) {
  return networkDisplacementSource(
      std::make_shared<const learned::DisplacementEnsemble>(std::vector<learned::DisplacementModel>{*model}),
      std::move(imu), std::move(thrust), repeat_next_at);
}

}  // namespace hdvio
