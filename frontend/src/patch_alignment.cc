#include "hdvio/frontend/patch_alignment.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace hdvio::frontend {

Eigen::Matrix2d affineWarp(const CameraModel& camera, const Vec2& px_ref, const Vec3& f_ref,
                           double depth_ref, int level_ref, const Pose& T_cur_ref) {
  const double offset = kAlignHalf * (1 << level_ref);
  const Vec3 xyz_ref = f_ref * depth_ref;
  Vec3 xyz_du = camera.unproject(px_ref + Vec2(offset, 0.0));
  Vec3 xyz_dv = camera.unproject(px_ref + Vec2(0.0, offset));
  xyz_du *= xyz_ref.z() / xyz_du.z();
  xyz_dv *= xyz_ref.z() / xyz_dv.z();
  Vec2 px_cur, px_du, px_dv;
  Eigen::Matrix2d A = Eigen::Matrix2d::Identity();
  if (!camera.project(T_cur_ref * xyz_ref, &px_cur) || !camera.project(T_cur_ref * xyz_du, &px_du) ||
      !camera.project(T_cur_ref * xyz_dv, &px_dv))
    return A;
  // Columns: level-0 pixels in the current image per pixel of the reference level (SVO), so
  // det(A) ~ 4^level_ref without motion and the search level follows the reference level.
  A.col(0) = (px_du - px_cur) / kAlignHalf;
  A.col(1) = (px_dv - px_cur) / kAlignHalf;
  return A;
}

int bestSearchLevel(const Eigen::Matrix2d& A, int max_level) {
  double d = A.determinant();
  int level = 0;
  while (d > 3.0 && level < max_level) {
    ++level;
    d *= 0.25;
  }
  return level;
}

bool warpPatch(const Eigen::Matrix2d& A_cur_ref, const cv::Mat& ref_img, const Vec2& px_ref,
               int level_ref, int search_level, BorderedPatch* patch) {
  if (std::abs(A_cur_ref.determinant()) < 1e-6) return false;
  const Eigen::Matrix2f A_ref_cur = A_cur_ref.inverse().cast<float>();
  const Eigen::Vector2f center = px_ref.cast<float>() / static_cast<float>(1 << level_ref);
  const float search_scale = static_cast<float>(1 << search_level);
  constexpr int kHalf = kBorderedPatch / 2;
  // The map is affine, so the patch is inside the image if its corners are; the margin keeps
  // the interior's rounding inside too. Then no pixel needs a check of its own.
  const float lo = -static_cast<float>(kHalf) * search_scale;
  const float hi = static_cast<float>(kBorderedPatch - 1 - kHalf) * search_scale;
  constexpr float kMargin = 1e-3f;
  for (const float oy : {lo, hi}) {
    for (const float ox : {lo, hi}) {
      const Eigen::Vector2f p = center + A_ref_cur * Eigen::Vector2f(ox, oy);
      if (p.x() < kMargin || p.y() < kMargin || p.x() >= ref_img.cols - 1 - kMargin ||
          p.y() >= ref_img.rows - 1 - kMargin)
        return false;
    }
  }
  const float a00 = A_ref_cur(0, 0), a01 = A_ref_cur(0, 1), a10 = A_ref_cur(1, 0), a11 = A_ref_cur(1, 1);
  for (int y = 0, k = 0; y < kBorderedPatch; ++y) {
    const float oy = static_cast<float>(y - kHalf) * search_scale;
    const float row_x = center.x() + a01 * oy, row_y = center.y() + a11 * oy;
    for (int x = 0; x < kBorderedPatch; ++x, ++k) {
      const float ox = static_cast<float>(x - kHalf) * search_scale;
      (*patch)[k] = interpolate(ref_img, row_x + a00 * ox, row_y + a10 * ox);
    }
  }
  return true;
}

bool warpPatchFromPyramid(const Eigen::Matrix2d& A_cur_ref, const Pyramid& ref_pyramid,
                          const Vec2& px_ref, int level_ref, int search_level, BorderedPatch* patch) {
  const int max_ref = static_cast<int>(ref_pyramid.size()) - 1;
  const int natural = bestSearchLevel(A_cur_ref, 30);
  const int r = std::clamp(level_ref + search_level - natural, 0, max_ref);
  // A maps pixels of level_ref; a pixel of level r is 2^(r - level_ref) of them.
  const Eigen::Matrix2d A_r = A_cur_ref * std::ldexp(1.0, r - level_ref);
  return warpPatch(A_r, ref_pyramid[r], px_ref, r, search_level, patch);
}

int refineToFinerLevels(const Pyramid& cur, const Eigen::Matrix2d& A_cur_ref,
                        const Pyramid& ref_pyramid, const Vec2& px_ref, int level_ref, int level,
                        Vec2* p) {
  while (level > 0) {
    BorderedPatch patch;
    if (!warpPatchFromPyramid(A_cur_ref, ref_pyramid, px_ref, level_ref, level - 1, &patch)) break;
    Vec2 q = 2.0 * *p;
    if (!align2D(cur[level - 1], patch, 10, &q) || (q - 2.0 * *p).norm() > 2.0) break;
    *p = q;
    --level;
  }
  return level;
}

bool align2D(const cv::Mat& img, const BorderedPatch& ref, int max_iterations, Vec2* px) {
  constexpr int kB = kBorderedPatch;
  constexpr int kP = kAlignPatch;
  // Patch arrays are indexed (x, y): a column per image row, so Eigen's fixed-size array
  // arithmetic below runs in SIMD registers (SSE or NEON) without hand-written intrinsics.
  using PatchArray = Eigen::Array<float, kP, kP>;
  // Gradients of the reference patch interior and the 3x3 Gauss-Newton matrix (fixed).
  PatchArray gx, gy, intensity;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (int y = 0; y < kP; ++y) {
    for (int x = 0; x < kP; ++x) {
      const int i = (y + 1) * kB + x + 1;
      gx(x, y) = 0.5f * (ref[i + 1] - ref[i - 1]);
      gy(x, y) = 0.5f * (ref[i + kB] - ref[i - kB]);
      intensity(x, y) = ref[i];
      const Eigen::Vector3d J(gx(x, y), gy(x, y), 1.0);
      H += J * J.transpose();
    }
  }
  const Eigen::LDLT<Eigen::Matrix3d> solver(H);
  if (solver.info() != Eigen::Success || std::abs(H.determinant()) < 1e-3) return false;
  const int stride = static_cast<int>(img.step.p[0]);
  double u = px->x(), v = px->y(), offset = 0.0;
  Eigen::Array<float, kP + 1, kP + 1> block;  // the pixels the bilinear lookups touch
  for (int it = 0; it < max_iterations; ++it) {
    if (u < kAlignHalf + 1 || v < kAlignHalf + 1 || u >= img.cols - kAlignHalf - 2 ||
        v >= img.rows - kAlignHalf - 2)
      return false;
    // Every pixel of the patch has the same sub-pixel offset: one set of bilinear weights (SVO).
    const double left = u - kAlignHalf, top = v - kAlignHalf;
    const int x0 = static_cast<int>(left), y0 = static_cast<int>(top);
    const float a = static_cast<float>(left - x0), c = static_cast<float>(top - y0);
    for (int y = 0; y <= kP; ++y) {
      const unsigned char* p = img.data + (y0 + y) * stride + x0;
      for (int x = 0; x <= kP; ++x) block(x, y) = p[x];
    }
    const PatchArray r = (1.f - a) * (1.f - c) * block.topLeftCorner<kP, kP>() +
                         a * (1.f - c) * block.bottomLeftCorner<kP, kP>() +
                         (1.f - a) * c * block.topRightCorner<kP, kP>() +
                         a * c * block.bottomRightCorner<kP, kP>() - intensity -
                         static_cast<float>(offset);
    const Eigen::Vector3d b((r * gx).sum(), (r * gy).sum(), r.sum());
    const Eigen::Vector3d d = solver.solve(b);
    if (!d.allFinite()) return false;
    u -= d.x();
    v -= d.y();
    offset += d.z();
    if (d.head<2>().squaredNorm() < 0.03 * 0.03) {
      *px = Vec2(u, v);
      return true;
    }
  }
  return false;
}

double zmssd(const cv::Mat& img, const BorderedPatch& ref, int x0, int y0) {
  double sum_ref = 0.0, sum_cur = 0.0, sum_sq = 0.0;
  for (int y = 0; y < kAlignPatch; ++y) {
    const unsigned char* row = img.ptr<unsigned char>(y0 - kAlignHalf + y) + x0 - kAlignHalf;
    for (int x = 0; x < kAlignPatch; ++x) {
      const double a = ref[(y + 1) * kBorderedPatch + x + 1], c = row[x];
      sum_ref += a;
      sum_cur += c;
      sum_sq += (c - a) * (c - a);
    }
  }
  const double n = kAlignPatch * kAlignPatch;
  return sum_sq - (sum_cur - sum_ref) * (sum_cur - sum_ref) / n;
}

}  // namespace hdvio::frontend
