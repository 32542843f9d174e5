#include "hdvio/learned/thrust_identification.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "hdvio/core/error.h"

namespace hdvio::learned {
namespace {

template <class Sample, class Get>
bool interpolateAt(const std::vector<Sample>& s, Timestamp t, Get get, Vec3* out) {
  if (s.empty() || t < s.front().t || t > s.back().t) return false;
  const auto hi = std::lower_bound(s.begin(), s.end(), t,
                                   [](const Sample& a, Timestamp v) { return a.t < v; });
  if (hi->t == t) {
    *out = get(*hi);
    return true;
  }
  const auto lo = hi - 1;
  const double a = static_cast<double>(t - lo->t) / static_cast<double>(hi->t - lo->t);
  *out = (1.0 - a) * get(*lo) + a * get(*hi);
  return true;
}

bool bodyVelocityAt(const std::vector<GroundTruthState>& gt, Timestamp t, Vec3* v_body) {
  Vec3 v_W;
  if (!interpolateAt(gt, t, [](const GroundTruthState& g) -> Vec3 { return g.v_W; }, &v_W)) return false;
  const auto hi = std::lower_bound(gt.begin(), gt.end(), t,
                                   [](const GroundTruthState& a, Timestamp v) { return a.t < v; });
  *v_body = hi->T_WB.q.conjugate() * v_W;
  return true;
}

}  // namespace

Vec3 predictFittedForce(const ThrustFit& fit, const Eigen::Vector4d& speeds, const Vec3& v_body) {
  return fit.c_over_m * speeds.squaredNorm() * fit.thrust_axis -
         fit.linear_drag.cwiseProduct(v_body);
}

ThrustFit fitThrust(const Sequence& seq, const ThrustFitOptions& options) {
  const std::string where = seq.source.empty() ? seq.name : seq.source;
  if (seq.rotor.empty()) throw InputError(where, 0, "sequence has no rotor speeds to fit a thrust coefficient");
  if (seq.imu.empty()) throw InputError(where, 0, "sequence has no IMU samples to fit a thrust coefficient");
  const bool drag = options.fit_linear_drag;
  const bool gt_velocity = !seq.groundtruth.empty() &&
      std::all_of(seq.groundtruth.begin(), seq.groundtruth.end(), [](const auto& g) { return g.has_velocity; });
  if (drag && !gt_velocity) throw InputError(where, 0, "fitting linear drag needs ground-truth velocity");
  const bool biases = !seq.groundtruth.empty() &&
      std::all_of(seq.groundtruth.begin(), seq.groundtruth.end(), [](const auto& g) { return g.has_biases; });
  const Vec3 axis = options.thrust_axis.normalized();

  std::vector<double> s2;   // sum of squared rotor speeds
  std::vector<Vec3> acc, vb;
  for (const auto& r : seq.rotor) {
    if (r.speeds.cwiseAbs().maxCoeff() < options.min_rotor_speed) continue;
    Vec3 a, v = Vec3::Zero();
    if (!interpolateAt(seq.imu, r.t, [](const ImuSample& s) -> Vec3 { return s.accel; }, &a)) continue;
    if (biases) {
      Vec3 ba;
      if (interpolateAt(seq.groundtruth, r.t, [](const GroundTruthState& g) -> Vec3 { return g.accel_bias; }, &ba)) a -= ba;
    }
    if (drag && !bodyVelocityAt(seq.groundtruth, r.t, &v)) continue;
    s2.push_back(r.speeds.squaredNorm());
    acc.push_back(a);
    vb.push_back(v);
  }
  const std::size_t n = s2.size();
  if (n < 100) throw InputError(where, 0, "fewer than 100 usable rotor samples for the thrust fit");

  ThrustFit fit;
  fit.samples = n;
  // Along the axis: a.axis = c s2 - d_z v.axis; across it (drag only): a_perp = -d v_perp.
  const int cols = drag ? 2 : 1;
  Eigen::MatrixXd A(n, cols);
  Eigen::VectorXd b(n);
  for (std::size_t k = 0; k < n; ++k) {
    A(k, 0) = s2[k];
    if (drag) A(k, 1) = -vb[k].dot(axis);
    b(k) = acc[k].dot(axis);
  }
  const Eigen::VectorXd x = A.colPivHouseholderQr().solve(b);
  fit.c_over_m = x(0);
  fit.thrust_axis = axis;
  if (fit.c_over_m < 0.0) {  // thrust points along -axis (e.g. an IMU with z down)
    fit.c_over_m = -fit.c_over_m;
    fit.thrust_axis = -axis;
  }
  if (drag) {
    // Drag across the axis, per body axis, on the components orthogonal to the thrust axis.
    Vec3 d = Vec3::Zero();
    for (int i = 0; i < 3; ++i) {
      double num = 0.0, den = 0.0;
      for (std::size_t k = 0; k < n; ++k) {
        const Vec3 a_perp = acc[k] - acc[k].dot(axis) * axis;
        const Vec3 v_perp = vb[k] - vb[k].dot(axis) * axis;
        num += -a_perp(i) * v_perp(i);
        den += v_perp(i) * v_perp(i);
      }
      d(i) = den > 0.0 ? num / den : 0.0;
    }
    d += x(1) * axis.cwiseAbs();  // along-axis drag on the axis' own component
    fit.linear_drag = d;
  }
  double se_axis = 0.0, se_total = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 model = fit.c_over_m * s2[k] * fit.thrust_axis - fit.linear_drag.cwiseProduct(vb[k]);
    se_axis += std::pow((acc[k] - model).dot(axis), 2);
    se_total += (acc[k] - model).squaredNorm();
  }
  fit.rmse_axis = std::sqrt(se_axis / n);
  fit.rmse_total = std::sqrt(se_total / n);
  return fit;
}

ThrustFit fitThrustJointly(const std::vector<Sequence>& flights, const ThrustFitOptions& options,
                           double begin, double end) {
  if (flights.empty()) throw InputError("", 0, "thrust fit: no flights");
  if (!(begin >= 0.0 && begin < end && end <= 1.0))
    throw InputError("", 0, "thrust fit: need 0 <= begin < end <= 1");
  Sequence all;
  all.name = "joint fit";
  for (const Sequence& s : flights) {
    if (s.imu.empty() || s.rotor.empty())
      throw InputError(s.name, 0, "thrust fit needs rotor speeds and IMU");
    const Timestamp shift = all.imu.empty() ? 0 : all.imu.back().t + kNanosPerSecond - s.imu.front().t;
    const auto n = static_cast<double>(s.rotor.size());
    const auto r0 = static_cast<std::size_t>(begin * n), r1 = static_cast<std::size_t>(end * n);
    for (std::size_t k = r0; k < r1; ++k) {
      RotorSample r = s.rotor[k];
      r.t += shift;
      all.rotor.push_back(r);
    }
    for (auto m : s.imu) { m.t += shift; all.imu.push_back(m); }
    for (auto g : s.groundtruth) { g.t += shift; all.groundtruth.push_back(g); }
  }
  return fitThrust(all, options);
}

}  // namespace hdvio::learned
