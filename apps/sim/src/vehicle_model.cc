#include "hdvio/sim/vehicle_model.h"

#include <cmath>
#include <sstream>

#include "hdvio/core/error.h"

namespace hdvio::sim {
namespace {

constexpr double kSmoothSpeedEps = 1e-3;  // m/s
constexpr int kMaxFixedPointIterations = 300;

Vec3 valueOf(const SVec3& v) { return Vec3(v.x.value(), v.y.value(), v.z.value()); }
Vec3 firstCoefficient(const SVec3& v) { return Vec3(v.x.c[1], v.y.c[1], v.z.c[1]); }

[[noreturn]] void impossible(double time, const std::string& what) {
  std::ostringstream s;
  s << "trajectory is not flyable at t = " << time << " s: " << what;
  throw InputError("", 0, s.str());
}

// Body axes from the thrust direction and yaw (ZYX-like flatness construction).
SMat3 attitude(const SVec3& thrust_direction, const Series& yaw, double time) {
  if (std::sqrt(dot(thrust_direction, thrust_direction).value()) < 0.5)
    impossible(time, "needed thrust below 0.5 m/s^2 (free fall)");
  SMat3 R;
  R.col[2] = normalized(thrust_direction);
  Series sy, cy;
  sincos(yaw, &sy, &cy);
  const SVec3 heading(cy, sy, Series(0.0));
  const SVec3 y = cross(R.col[2], heading);
  if (std::sqrt(dot(y, y).value()) < 0.05) impossible(time, "thrust axis is horizontal along the heading");
  R.col[1] = normalized(y);
  R.col[0] = cross(R.col[1], R.col[2]);
  return R;
}

// Largest coefficient change relative to the coefficient sizes (orders differ in scale).
double relativeChange(const SMat3& A, const SMat3& B) {
  double d = 0.0, scale = 1.0;
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < kSeriesOrder; ++k) {
        d = std::max(d, std::abs(A.col[c][i].c[k] - B.col[c][i].c[k]));
        scale = std::max(scale, std::abs(A.col[c][i].c[k]));
      }
  return d / scale;
}

}  // namespace

VehicleModel::VehicleModel(const SimConfig& config)
    : vehicle_(config.vehicle),
      trajectory_(config.trajectory, config.yaw, config.scene, config.duration, config.seed),
      wind_(config.wind, config.seed),
      forces_(config.forces, config.vehicle.mass) {
  // Rows: total thrust, roll torque, pitch torque, yaw torque per rotor thrust (N).
  const double l = vehicle_.arm_length / std::sqrt(2.0), k = vehicle_.torque_coefficient;
  const double x[4] = {l, -l, -l, l}, y[4] = {-l, -l, l, l}, spin[4] = {-1.0, 1.0, -1.0, 1.0};
  Eigen::Matrix4d A;
  for (int i = 0; i < 4; ++i) A.col(i) = Eigen::Vector4d(1.0, y[i], -x[i], spin[i] * k);
  allocation_inverse_ = A.inverse();
  // Fail early (with the time) if the flight needs impossible thrust.
  for (double t = 0.0; t <= config.duration + 1e-9; t += 0.05) evaluate(t);
}

TrueState VehicleModel::evaluate(double time) const {
  const Series t = Series::variable(time);
  const SVec3 p = trajectory_.position(t);
  const SVec3 v = derivative(p);
  const SVec3 a = derivative(v);
  const Series yaw = trajectory_.yaw(t, p);
  const SVec3 wind = wind_.velocity(p, t);
  const SVec3 ext_W = forces_.force(t, a);
  const SVec3 a_minus_g = a - SVec3(0.0, 0.0, -kGravity);
  const SVec3 v_rel = v - wind;
  const Series speed = sqrt(dot(v_rel, v_rel) + kSmoothSpeedEps * kSmoothSpeedEps);
  const Vec3& D = vehicle_.rotor_drag;

  auto dragBody = [&](const SMat3& R) {
    const SVec3 vb = R.transposeTimes(v_rel);
    return SVec3(-D.x() * vb.x, -D.y() * vb.y, -D.z() * vb.z) - vb * (vehicle_.fuselage_drag * speed);
  };

  SMat3 R = attitude(a_minus_g - ext_W, yaw, time);
  bool converged = false;
  for (int it = 0; it < kMaxFixedPointIterations; ++it) {
    const SMat3 next = attitude(a_minus_g - ext_W - R * dragBody(R), yaw, time);
    const double change = relativeChange(next, R);
    R = next;
    if (change < 1e-14) {
      converged = true;
      break;
    }
  }
  if (!converged) impossible(time, "drag is too strong relative to the needed thrust (attitude fixed point did not converge)");

  const SVec3 drag = dragBody(R);
  const SVec3 ext_B = R.transposeTimes(ext_W);
  const SVec3 specific = R.transposeTimes(a_minus_g);
  const SVec3 thrust = specific - drag - ext_B;

  // Body rates: Omega = R^T dR/dt, omega = vee(Omega); its series' first coefficient is omega_dot.
  SVec3 dcol[3];
  for (int c = 0; c < 3; ++c) dcol[c] = derivative(R.col[c]);
  const SVec3 omega(dot(R.col[2], dcol[1]), dot(R.col[0], dcol[2]), dot(R.col[1], dcol[0]));

  TrueState s;
  s.time = time;
  s.p = valueOf(p);
  s.v = valueOf(v);
  s.a = valueOf(a);
  for (int c = 0; c < 3; ++c) s.R.col(c) = valueOf(R.col[c]);
  s.omega = valueOf(omega);
  s.omega_dot = firstCoefficient(omega);
  s.specific_force = valueOf(specific);
  s.thrust = thrust.z.value();
  s.thrust_rate = thrust.z.c[1];
  s.thrust_residual_xy = Vec3(thrust.x.value(), thrust.y.value(), 0.0);
  s.drag = valueOf(drag);
  s.external = valueOf(ext_B);
  s.wind = valueOf(wind);
  return s;
}

Eigen::Vector4d VehicleModel::rotorSpeeds(const TrueState& s, double collective, bool* clamped) const {
  const Vec3 J = vehicle_.inertia;
  const Vec3 torque = J.asDiagonal() * s.omega_dot + s.omega.cross(J.asDiagonal() * s.omega);
  const Eigen::Vector4d wrench(vehicle_.mass * collective, torque.x(), torque.y(), torque.z());
  Eigen::Vector4d f = allocation_inverse_ * wrench;
  Eigen::Vector4d w;
  for (int i = 0; i < 4; ++i) {
    if (f[i] < 0.0) {
      *clamped = true;
      f[i] = 0.0;
    }
    w[i] = std::sqrt(f[i] / vehicle_.thrust_coefficient);
  }
  return w;
}

}  // namespace hdvio::sim
