#include "hdvio/frontend/pose_optimizer.h"

#include <cmath>

#include <Eigen/Cholesky>

namespace hdvio::frontend {
namespace {

using Vec2 = Eigen::Vector2d;
using Mat23 = Eigen::Matrix<double, 2, 3>;

Vec2 unitPlane(const Vec3& v) { return v.head<2>() / v.z(); }

Mat23 unitPlaneJacobian(const Vec3& p) {
  const double iz = 1.0 / p.z();
  Mat23 J;
  J << iz, 0.0, -p.x() * iz * iz, 0.0, iz, -p.y() * iz * iz;
  return J;
}

}  // namespace

PoseOptimizerResult optimizePose(const Pose& T_cw_guess, const std::vector<PoseObservation>& obs,
                                 double focal, const PoseOptimizerOptions& options) {
  PoseOptimizerResult result;
  Pose T = T_cw_guess;
  const double huber = options.huber_px / focal;
  for (int it = 0; it < options.iterations; ++it) {
    Mat6 H = Mat6::Zero();
    Vec6 g = Vec6::Zero();
    for (const PoseObservation& o : obs) {
      const Vec3 p_c = T * o.p_w;
      if (p_c.z() < 1e-6) continue;
      const Vec2 e = unitPlane(p_c) - unitPlane(o.f);
      const double level_scale = 1.0 / (1 << o.level);  // coarser level: larger noise
      const double norm = e.norm() * level_scale;
      const double w = level_scale * level_scale * (norm <= huber ? 1.0 : huber / norm);
      Eigen::Matrix<double, 3, 6> dp;
      dp << Mat3::Identity(), -hat(p_c);
      const Eigen::Matrix<double, 2, 6> J = unitPlaneJacobian(p_c) * dp;
      H.noalias() += w * J.transpose() * J;
      g.noalias() += w * J.transpose() * e;
    }
    const Vec6 delta = -H.ldlt().solve(g);
    if (!delta.allFinite()) break;
    T = se3Exp(delta) * T;
    if (delta.squaredNorm() < 1e-14) break;
  }
  result.T_cw = T;
  result.inlier.assign(obs.size(), 0);
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const Vec3 p_c = T * obs[i].p_w;
    if (p_c.z() < 1e-6) continue;
    const double err_px = (unitPlane(p_c) - unitPlane(obs[i].f)).norm() * focal;
    if (err_px > options.outlier_px * (1 << obs[i].level)) continue;
    result.inlier[i] = 1;
    ++result.inliers;
    sum_sq += err_px * err_px;
  }
  result.rms_px = result.inliers > 0 ? std::sqrt(sum_sq / result.inliers) : 0.0;
  return result;
}

bool optimizePoint(const std::vector<PointObservation>& obs, int iterations, Vec3* p_w) {
  if (obs.size() < 2) return false;
  auto cost = [&](const Vec3& p, bool* in_front) {
    double c = 0.0;
    *in_front = true;
    for (const PointObservation& o : obs) {
      const Vec3 p_c = o.T_cw * p;
      if (p_c.z() < 1e-6) *in_front = false;
      else c += (unitPlane(p_c) - unitPlane(o.f)).squaredNorm();
    }
    return c;
  };
  bool in_front = true;
  Vec3 p = *p_w;
  double c = cost(p, &in_front);
  if (!in_front) return false;
  const double c0 = c;
  for (int it = 0; it < iterations; ++it) {
    Mat3 H = Mat3::Zero();
    Vec3 g = Vec3::Zero();
    for (const PointObservation& o : obs) {
      const Vec3 p_c = o.T_cw * p;
      const Eigen::Matrix<double, 2, 3> J = unitPlaneJacobian(p_c) * o.T_cw.R();
      H.noalias() += J.transpose() * J;
      g.noalias() += J.transpose() * (unitPlane(p_c) - unitPlane(o.f));
    }
    const Vec3 candidate = p - H.ldlt().solve(g);
    const double c_new = candidate.allFinite() ? cost(candidate, &in_front) : c;
    if (!candidate.allFinite() || !in_front || c_new >= c) break;
    p = candidate;
    c = c_new;
  }
  if (c >= c0) return false;
  *p_w = p;
  return true;
}

}  // namespace hdvio::frontend
