#include "hdvio/frontend/sparse_image_alignment.h"

#include <cmath>

#include <Eigen/Cholesky>

namespace hdvio::frontend {
namespace {

constexpr int kPatch = 4;  // 4x4 patches
constexpr int kHalf = 2;
constexpr int kArea = kPatch * kPatch;
using Vec6f = Eigen::Matrix<double, 6, 1>;

// Reference patches and inverse-compositional Jacobians of one pyramid level.
struct RefPatches {
  std::vector<float> intensity;             // kArea per point
  std::vector<Vec6f> jacobian;              // kArea per point
  std::vector<char> valid;                  // per point
};

RefPatches precompute(const CameraModel& camera, const cv::Mat& img, int level,
                      const std::vector<Vec3>& points) {
  RefPatches ref;
  const std::size_t n = points.size();
  ref.intensity.resize(n * kArea);
  ref.jacobian.resize(n * kArea);
  ref.valid.assign(n, 0);
  const double scale = 1.0 / (1 << level);
  for (std::size_t i = 0; i < n; ++i) {
    Vec2 px;
    Mat23 Jp;
    if (!camera.project(points[i], &px, &Jp)) continue;
    const double u = px.x() * scale, v = px.y() * scale;
    if (u < kHalf + 2 || v < kHalf + 2 || u >= img.cols - kHalf - 3 || v >= img.rows - kHalf - 3)
      continue;
    // d(level pixel)/d(twist [rho, phi]) of Exp(xi) * p at xi = 0.
    Eigen::Matrix<double, 3, 6> dp;
    dp << Mat3::Identity(), -hat(points[i]);
    const Eigen::Matrix<double, 2, 6> Jpx = scale * Jp * dp;
    for (int y = 0, k = 0; y < kPatch; ++y) {
      for (int x = 0; x < kPatch; ++x, ++k) {
        const float uu = static_cast<float>(u - kHalf + x), vv = static_cast<float>(v - kHalf + y);
        const float gx = 0.5f * (interpolate(img, uu + 1.f, vv) - interpolate(img, uu - 1.f, vv));
        const float gy = 0.5f * (interpolate(img, uu, vv + 1.f) - interpolate(img, uu, vv - 1.f));
        ref.intensity[i * kArea + k] = interpolate(img, uu, vv);
        ref.jacobian[i * kArea + k] = (gx * Jpx.row(0) + gy * Jpx.row(1)).transpose();
      }
    }
    ref.valid[i] = 1;
  }
  return ref;
}

struct Normal {
  Mat6 H = Mat6::Zero();
  Vec6 b = Vec6::Zero();
  double chi2 = 0.0;
  int pixels = 0;
  int patches = 0;
};

Normal accumulate(const CameraModel& camera, const cv::Mat& img, int level,
                  const std::vector<Vec3>& points, const RefPatches& ref, const Pose& T,
                  double huber) {
  Normal n;
  const double scale = 1.0 / (1 << level);
  const Mat3 R = T.R();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!ref.valid[i]) continue;
    Vec2 px;
    if (!camera.project(R * points[i] + T.p, &px)) continue;
    const double u = px.x() * scale, v = px.y() * scale;
    if (u < kHalf + 1 || v < kHalf + 1 || u >= img.cols - kHalf - 2 || v >= img.rows - kHalf - 2)
      continue;
    ++n.patches;
    for (int y = 0, k = 0; y < kPatch; ++y) {
      for (int x = 0; x < kPatch; ++x, ++k) {
        const double r = interpolate(img, static_cast<float>(u - kHalf + x),
                                     static_cast<float>(v - kHalf + y)) -
                         ref.intensity[i * kArea + k];
        const double a = std::abs(r);
        const double w = a <= huber ? 1.0 : huber / a;
        const Vec6& J = ref.jacobian[i * kArea + k];
        n.H.noalias() += w * J * J.transpose();
        n.b.noalias() += w * r * J;
        n.chi2 += a <= huber ? r * r : huber * (2.0 * a - huber);
        ++n.pixels;
      }
    }
  }
  return n;
}

}  // namespace

SparseAlignmentResult alignSparse(const CameraModel& camera, const Pyramid& ref,
                                  const std::vector<Vec3>& points_ref, const Pyramid& cur,
                                  const Pose& T_cur_ref_guess,
                                  const std::optional<Quat>& rotation_prior,
                                  const SparseAlignmentOptions& options) {
  SparseAlignmentResult result;
  Pose T = T_cur_ref_guess;
  const int max_level = std::min<int>(options.max_level, static_cast<int>(ref.size()) - 1);
  const double prior_weight =
      std::pow(options.intensity_sigma / options.rotation_prior_sigma, 2);
  for (int level = max_level; level >= options.min_level; --level) {
    const RefPatches patches = precompute(camera, ref[level], level, points_ref);
    double prev_cost = std::numeric_limits<double>::infinity();
    Pose T_prev = T;
    Normal n;
    for (int it = 0; it < options.max_iterations; ++it) {
      n = accumulate(camera, cur[level], level, points_ref, patches, T, options.huber_threshold);
      if (n.pixels < kArea * 4) break;
      double cost = n.chi2;
      if (rotation_prior) {
        // Linearized prior on the rotation of T * Exp(xi)^-1: e(phi) ~ e0 - phi.
        const Vec3 e0 = quatLog(rotation_prior->conjugate() * T.q);
        n.H.bottomRightCorner<3, 3>() += prior_weight * Mat3::Identity();
        n.b.tail<3>() += prior_weight * e0;
        cost += prior_weight * e0.squaredNorm();
      }
      cost /= n.pixels;
      if (cost > prev_cost) {  // the last step made things worse: undo it and stop
        T = T_prev;
        break;
      }
      prev_cost = cost;
      const Vec6 xi = n.H.ldlt().solve(n.b);
      if (!xi.allFinite()) break;
      T_prev = T;
      T = T * se3Exp(xi).inverse();
      if (xi.squaredNorm() < 1e-12) break;
    }
    if (level == options.min_level) {
      result.patches = n.patches;
      result.rms_error = n.pixels > 0 ? std::sqrt(n.chi2 / n.pixels) : 0.0;
    }
  }
  result.T_cur_ref = T;
  result.ok = result.patches >= 5 && T.p.allFinite() && T.q.coeffs().allFinite();
  return result;
}

}  // namespace hdvio::frontend
