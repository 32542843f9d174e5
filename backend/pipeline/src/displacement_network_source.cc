#include "hdvio/pipeline/displacement_network_source.h"

#include <utility>

namespace hdvio {

imo::DisplacementSource networkDisplacementSource(
    std::shared_ptr<const learned::DisplacementModel> model,
    std::shared_ptr<const std::vector<ImuSample>> imu,
    std::shared_ptr<const std::vector<ThrustSample>> thrust) {
  const bool use_thrust = model->inputKind() == learned::DisplacementInputKind::kThrustGyro;
  const Timestamp w = model->windowDuration();
  auto covered = [w](const auto& stream, Timestamp t_end) {
    return !stream.empty() && stream.front().t <= t_end - w && stream.back().t >= t_end;
  };
  return [model = std::move(model), imu = std::move(imu), thrust = std::move(thrust), use_thrust,
          covered](const imo::DisplacementRequest& r) -> std::optional<imo::DisplacementEstimate> {
    if (!covered(*imu, r.t_end) || (use_thrust && !covered(*thrust, r.t_end))) return std::nullopt;
    const learned::MatrixXf window = learned::makeDisplacementWindow(
        *model, *imu, *thrust, r.t_end, r.world_from_body, r.gyro_bias, r.accel_bias);
    const learned::DisplacementPrediction p = model->predict(window);
    imo::DisplacementEstimate e;
    e.z = p.displacement;
    e.covariance = p.covariance;
    return e;
  };
}

}  // namespace hdvio
