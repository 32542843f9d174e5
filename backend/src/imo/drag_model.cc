#include "hdvio/backend/imo/drag_model.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "hdvio/core/sequence.h"
#include "hdvio/core/error.h"

namespace hdvio::imo {

std::vector<DragSample> collectDragSamples(const Sequence& seq, const std::vector<ThrustSample>& thrust) {
  std::vector<DragSample> out;
  if (seq.groundtruth.empty() || thrust.empty()) return out;
  if (!seq.groundtruth.front().has_velocity)
    throw InputError(seq.source, 0, "the drag fit needs ground-truth velocity");
  const Timestamp t0 = std::max(thrust.front().t, seq.groundtruth.front().t);
  const Timestamp t1 = std::min(thrust.back().t, seq.groundtruth.back().t);
  for (const ImuSample& m : seq.imu) {
    if (m.t < t0 || m.t > t1) continue;
    const NavState gt = groundTruthState(seq, m.t);
    DragSample s;
    s.specific_force = m.accel;
    s.thrust = *thrustAt(thrust, m.t);
    s.R = gt.T_WB.R();
    s.velocity_body = s.R.transpose() * gt.v_W;
    out.push_back(s);
  }
  return out;
}

namespace {

Vec3 modelForce(const DragModel& m, const DragSample& s) {
  return m.thrust_scale * s.thrust - m.drag.linear.cwiseProduct(s.velocity_body);
}

void residualStats(const std::vector<DragSample>& samples, const DragModel& m, Vec3* mean, Vec3* rms) {
  Vec3 sum = Vec3::Zero(), sq = Vec3::Zero();
  for (const DragSample& s : samples) {
    const Vec3 r = s.R * (s.specific_force - modelForce(m, s));
    sum += r;
    sq += r.cwiseAbs2();
  }
  const double n = static_cast<double>(samples.size());
  *mean = sum / n;
  *rms = (sq / n).cwiseSqrt();
}

}  // namespace

DragFit fitDragModel(const std::vector<DragSample>& samples, bool fit_thrust_scale) {
  if (samples.size() < 100)
    throw InputError("", 0, "drag fit: fewer than 100 samples with thrust and ground truth");
  // Unknowns [k, d_x, d_y, d_z]; axis a of a sample: f_a = k T_a - d_a v_a.
  Eigen::Matrix4d N = Eigen::Matrix4d::Zero();
  Eigen::Vector4d b = Eigen::Vector4d::Zero();
  for (const DragSample& s : samples) {
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector4d row = Eigen::Vector4d::Zero();
      double y = s.specific_force(a);
      if (fit_thrust_scale) row(0) = s.thrust(a);
      else y -= s.thrust(a);
      row(1 + a) = -s.velocity_body(a);
      N += row * row.transpose();
      b += row * y;
    }
  }
  if (!fit_thrust_scale) N(0, 0) = 1.0;  // k fixed: keep the system regular (b(0) = 0)
  const Eigen::Vector4d x = N.ldlt().solve(b);
  DragFit fit;
  fit.samples = samples.size();
  fit.model.thrust_scale = fit_thrust_scale ? x(0) : 1.0;
  fit.model.drag.linear = x.tail<3>();
  residualStats(samples, DragModel{}, &fit.mean_thrust_only, &fit.rms_thrust_only);
  residualStats(samples, fit.model, &fit.mean_fitted, &fit.rms_fitted);
  return fit;
}

DragLawFit fitDragLawOnSamples(const std::vector<DragSample>& samples, double thrust_scale) {
  if (samples.size() < 100)
    throw InputError("", 0, "drag fit: fewer than 100 samples with thrust and ground truth");
  std::vector<Vec3> u, f;
  std::vector<double> thrust;
  for (const DragSample& s : samples) {
    u.push_back(s.velocity_body);
    thrust.push_back(thrust_scale * s.thrust.norm());
    f.push_back(s.specific_force - thrust_scale * s.thrust);
  }
  DragLawFit fit;
  fit.law = hdvio::fitDragLaw(u, thrust, f);
  Vec3 sum_sq = Vec3::Zero();
  for (std::size_t k = 0; k < samples.size(); ++k)
    sum_sq += (samples[k].R * (f[k] - fit.law.force(u[k], thrust[k]))).cwiseAbs2();
  fit.rms = (sum_sq / static_cast<double>(samples.size())).cwiseSqrt();
  return fit;
}

namespace {

// p_end - p_begin = C v_begin + d for v' = -A(t) v + a(t), A = R D R^T, a = R k T + g, with the
// world rotations perturbed by E on the left. Midpoint steps, inputs held at the step midpoints.
void integrateModel(const std::vector<Mat3>& R, const std::vector<Vec3>& kT, const Vec3& drag,
                    const Mat3& E, double h, const Vec3& gravity, Mat3* C, Vec3* d) {
  Vec3 u = Vec3::Zero(), z = Vec3::Zero();
  Mat3 Phi = Mat3::Identity(), Psi = Mat3::Zero();
  for (std::size_t m = 0; m < R.size(); ++m) {
    const Mat3 Rm = E * R[m];
    const Mat3 A = Rm * drag.asDiagonal() * Rm.transpose();
    const Vec3 a = Rm * kT[m] + gravity;
    const Vec3 u_half = u + 0.5 * h * (a - A * u);
    z += h * u_half;
    u += h * (a - A * u_half);
    const Mat3 Phi_half = Phi - 0.5 * h * A * Phi;
    Psi += h * Phi_half;
    Phi -= h * A * Phi_half;
  }
  *C = Psi;
  *d = z;
}

}  // namespace

DisplacementSource makeDragModelSource(std::vector<ThrustSample> thrust, const DragModel& model,
                                       double step_s, const Vec3& sigma, const Vec3& gravity,
                                       bool attitude_jacobian) {
  return makeDragModelSource(std::make_shared<const std::vector<ThrustSample>>(std::move(thrust)),
                             model, step_s, sigma, gravity, attitude_jacobian);
}

DisplacementSource makeDragModelSource(std::shared_ptr<const std::vector<ThrustSample>> samples,
                                       const DragModel& model, double step_s, const Vec3& sigma,
                                       const Vec3& gravity, bool attitude_jacobian) {
  if (!(step_s > 0.0)) throw std::invalid_argument("makeDragModelSource: step must be > 0");
  if (!model.drag.quadratic.isZero(0.0) || !model.drag.rotor.isZero(0.0))
    throw std::invalid_argument("makeDragModelSource: the Model-EKF takes linear drag only");
  const Mat3 cov = sigma.cwiseAbs2().asDiagonal();
  return [samples, model, step_s, cov, gravity, attitude_jacobian](const DisplacementRequest& r)
             -> std::optional<DisplacementEstimate> {
    if (samples->empty() || r.t_begin < samples->front().t || r.t_end > samples->back().t)
      return std::nullopt;
    const double window = secondsBetween(r.t_begin, r.t_end);
    const int n = std::max(1, static_cast<int>(std::lround(window / step_s)));
    const double h = window / n;
    std::vector<Mat3> R(n);
    std::vector<Vec3> kT(n);
    for (int m = 0; m < n; ++m) {
      const Timestamp t_mid = r.t_begin + fromSeconds((m + 0.5) * h);
      R[m] = r.world_from_body(t_mid).toRotationMatrix();
      kT[m] = model.thrust_scale * *thrustAt(*samples, t_mid);
    }
    DisplacementEstimate est;
    est.covariance = cov;
    integrateModel(R, kT, model.drag.linear, Mat3::Identity(), h, gravity, &est.velocity_matrix, &est.z);
    if (attitude_jacobian) {
      // R(t) = R_i Gamma(t): R_i Exp(dtheta) Gamma = Exp(R_i dtheta) R(t), so differentiate the
      // prediction C v_i + d for a left (world) rotation w and chain with dw/dtheta = R_i.
      const Mat3 R_i = r.world_from_body(r.t_begin).toRotationMatrix();
      constexpr double kEps = 1e-5;
      Mat3 J_world;
      for (int k = 0; k < 3; ++k) {
        Vec3 predicted[2];
        for (int sgn = 0; sgn < 2; ++sgn) {
          Mat3 C;
          Vec3 d;
          const Vec3 w = (sgn == 0 ? kEps : -kEps) * Vec3::Unit(k);
          integrateModel(R, kT, model.drag.linear, so3Exp(w), h, gravity, &C, &d);
          predicted[sgn] = C * r.velocity_begin + d;
        }
        J_world.col(k) = (predicted[0] - predicted[1]) / (2.0 * kEps);
      }
      est.attitude_jacobian = J_world * R_i;
    }
    return est;
  };
}

}  // namespace hdvio::imo
