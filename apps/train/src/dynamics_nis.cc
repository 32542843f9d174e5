#include "hdvio/train/dynamics_nis.h"

#include <memory>

#include <Eigen/Dense>

#include "hdvio/core/error.h"
#include "hdvio/factors/drag_model.h"
#include "hdvio/factors/point_mass_dynamics.h"

namespace hdvio::train {

DynamicsNis dynamicsNis(const learned::FlightSamples& f, const DragLaw& law, std::size_t samples,
                        const ThrustNoiseParams& noise) {
  if (f.force.size() != f.size()) throw InputError(f.name, 0, "dynamics NIS needs the flight's IMU");
  if (samples == 0 || f.size() <= samples)
    throw InputError(f.name, 0, "dynamics NIS: the flight is not longer than one interval");
  std::vector<ImuSample> imu;
  std::vector<ThrustSample> thrust;
  for (std::size_t k = 0; k < f.size(); ++k) {
    imu.push_back({f.t[k], f.gyro[k], f.force[k]});  // bias-free: the flight's known bias is removed
    thrust.push_back({f.t[k], f.thrust[k]});
  }
  DynamicsNis out;
  for (std::size_t i = 0; i + samples < f.size(); i += samples) {
    const std::size_t j = i + samples;
    auto pit = std::make_shared<const PreintegratedThrust>(
        PreintegratedThrust::integrate(imu, thrust, f.t[i], f.t[j], Vec6::Zero(), noise));
    const PointMassDynamics dynamics(pit, law);
    const Quat q_i = f.q_WB[i].normalized(), q_j = f.q_WB[j].normalized();
    double pose_i[7], pose_j[7], force[3] = {0.0, 0.0, 0.0}, bias[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    Eigen::Map<Vec3>{pose_i} = f.p_W[i];
    Eigen::Map<Quat>{pose_i + 3} = q_i;
    Eigen::Map<Vec3>{pose_j} = f.p_W[j];
    Eigen::Map<Quat>{pose_j + 3} = q_j;
    double residual[9];
    dynamics.evaluate({pose_i, f.v_W[i].data(), force, pose_j, f.v_W[j].data(), bias}, residual, nullptr);
    const Mat3 RiT = q_i.toRotationMatrix().transpose();
    const Mat6 C = pit->alphaBetaCovariance() + dragCovariance(*pit, law, RiT * f.v_W[i], RiT * f.v_W[j]);
    const Eigen::Map<const Vec6> r(residual);
    const Vec3 a = r.head<3>(), b = r.tail<3>();
    out.joint += r.dot(C.ldlt().solve(r));
    out.alpha += a.dot(C.topLeftCorner<3, 3>().ldlt().solve(a));
    out.beta += b.dot(C.bottomRightCorner<3, 3>().ldlt().solve(b));
    ++out.intervals;
  }
  const double n = static_cast<double>(out.intervals);
  out.joint /= 6.0 * n;
  out.alpha /= 3.0 * n;
  out.beta /= 3.0 * n;
  return out;
}

}  // namespace hdvio::train
