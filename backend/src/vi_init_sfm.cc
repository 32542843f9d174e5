#include "hdvio/backend/vi_init_sfm.h"

#include <ceres/ceres.h>
#include <ceres/manifold.h>
#include <ceres/sphere_manifold.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "hdvio/backend/triangulation.h"

namespace hdvio::vi_init {
namespace {

using Mat9 = Eigen::Matrix<double, 9, 9>;
using Vec9 = Eigen::Matrix<double, 9, 1>;

constexpr double kMinPointParallaxRad = 0.03;  // rays closer than this give depth noise only

struct Correspondence {
  int id;
  Vec3 x0, x1;  // bearings in the first and the reference camera
};

// Angular distance of each bearing from the epipolar plane of the other (max of both).
double epipolarError(const Mat3& E, const Correspondence& c) {
  const Vec3 n0 = E * c.x1, n1 = E.transpose() * c.x0;
  const double e0 = n0.norm() > 1e-12 ? std::abs(c.x0.dot(n0)) / n0.norm() : 1.0;
  const double e1 = n1.norm() > 1e-12 ? std::abs(c.x1.dot(n1)) / n1.norm() : 1.0;
  return std::max(e0, e1);
}

std::vector<int> inliersOf(const Mat3& E, const std::vector<Correspondence>& cs, double thr) {
  std::vector<int> in;
  for (std::size_t i = 0; i < cs.size(); ++i)
    if (epipolarError(E, cs[i]) < thr) in.push_back(static_cast<int>(i));
  return in;
}

// Linear eight-point essential matrix (x0^T E x1 = 0) from the given correspondences,
// projected onto the essential manifold.
Mat3 eightPoint(const std::vector<Correspondence>& cs, const std::vector<int>& idx) {
  Mat9 AtA = Mat9::Zero();
  for (int i : idx) {
    Vec9 row;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) row(3 * r + c) = cs[i].x0(r) * cs[i].x1(c);
    AtA += row * row.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Mat9> eig(AtA);
  const Vec9 e = eig.eigenvectors().col(0);
  Mat3 E;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) E(r, c) = e(3 * r + c);
  const Eigen::JacobiSVD<Mat3> svd(E, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * Vec3(1.0, 1.0, 0.0).asDiagonal() * svd.matrixV().transpose();
}

// Depths (d0, d1) with d0 x0 = d1 R x1 + t, least squares.
Eigen::Vector2d twoViewDepths(const Mat3& R, const Vec3& t, const Correspondence& c) {
  Eigen::Matrix<double, 3, 2> A;
  A.col(0) = c.x0;
  A.col(1) = -(R * c.x1);
  return (A.transpose() * A).ldlt().solve(A.transpose() * t);
}

struct TwoView {
  Mat3 R = Mat3::Identity();  // R_C0Cl
  Vec3 t = Vec3::Zero();      // position of camera l in camera 0, unit norm
  std::vector<int> inliers;
};

// RANSAC over two hypothesis generators, scored alike: two points with the gyro rotation
// (robust to planar scenes, needs a decent rotation) and eight points (no rotation needed).
TwoView twoViewGeometry(const std::vector<Correspondence>& cs, const Mat3& R_prior, double thr,
                        const SfmOptions& options) {
  std::mt19937 rng(options.seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(cs.size()) - 1);
  std::vector<int> best;
  Mat3 best_E = Mat3::Zero();
  const auto consider = [&](const Mat3& E) {
    if (!E.allFinite() || E.norm() < 1e-12) return;
    std::vector<int> in = inliersOf(E, cs, thr);
    if (in.size() > best.size()) {
      best = std::move(in);
      best_E = E;
    }
  };
  for (int it = 0; it < options.ransac_iterations; ++it) {
    if (it % 2 == 0) {
      const int i = pick(rng), j = pick(rng);
      if (i == j) continue;
      const Vec3 ai = (R_prior * cs[i].x1).cross(cs[i].x0);
      const Vec3 aj = (R_prior * cs[j].x1).cross(cs[j].x0);
      const Vec3 t = ai.cross(aj);
      if (t.norm() < 1e-12) continue;
      consider(hat(t.normalized()) * R_prior);
    } else {
      std::vector<int> sample;
      while (sample.size() < 8) {
        const int k = pick(rng);
        if (std::find(sample.begin(), sample.end(), k) == sample.end()) sample.push_back(k);
      }
      consider(eightPoint(cs, sample));
    }
  }
  // Re-estimate from all inliers when that does not lose support.
  if (best.size() >= 8) consider(eightPoint(cs, best));

  TwoView out;
  if (best.size() < 8) return out;
  const Eigen::JacobiSVD<Mat3> svd(best_E, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 U = svd.matrixU(), V = svd.matrixV();
  if (U.determinant() < 0) U = -U;
  if (V.determinant() < 0) V = -V;
  Mat3 W;
  W << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  int best_front = -1;
  for (const Mat3& R : {Mat3(U * W * V.transpose()), Mat3(U * W.transpose() * V.transpose())}) {
    for (const double sign : {1.0, -1.0}) {
      const Vec3 t = sign * U.col(2);
      int front = 0;
      for (int i : best) {
        const Eigen::Vector2d d = twoViewDepths(R, t, cs[i]);
        if (d(0) > 0 && d(1) > 0) ++front;
      }
      if (front > best_front) {
        best_front = front;
        out.R = R;
        out.t = t;
      }
    }
  }
  for (int i : best) {
    const Eigen::Vector2d d = twoViewDepths(out.R, out.t, cs[i]);
    if (d(0) > 0 && d(1) > 0) out.inliers.push_back(i);
  }
  return out;
}

// Reprojection error on the normalized image plane, scaled to pixels.
struct BearingReprojection {
  Eigen::Vector2d m;
  double focal;

  template <typename T>
  bool operator()(const T* q_data, const T* c_data, const T* x_data, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(q_data);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> c(c_data), x(x_data);
    const Eigen::Matrix<T, 3, 1> p = q.conjugate() * (x - c);
    // Behind the camera: a large finite residual (the robust loss caps it) rather than a failed
    // evaluation, which Ceres would log on every rejected step.
    const T z = p.z() < T(1e-3) ? T(1e-3) : p.z();
    r[0] = T(focal) * (p.x() / z - T(m.x()));
    r[1] = T(focal) * (p.y() / z - T(m.y()));
    return true;
  }
};

struct Reconstruction {
  std::vector<Pose> T;  // T_C0C
  std::vector<bool> solved;
  std::map<int, Vec3> points;
};

double reprojectionErrorPx(const Pose& T_C0C, const Vec3& x, const Vec3& bearing, double focal) {
  const Vec3 p = T_C0C.inverse() * x;
  if (p.z() < 1e-6 || bearing.z() < 1e-6) return 1e9;
  return focal * (p.head<2>() / p.z() - bearing.head<2>() / bearing.z()).norm();
}

// Triangulates every track seen by at least two solved frames with enough parallax.
void triangulateAll(const std::vector<BearingFrame>& frames, Reconstruction* rec,
                    bool keep_existing) {
  std::map<int, std::pair<std::vector<Pose>, std::vector<Vec3>>> rays;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    if (!rec->solved[k]) continue;
    for (const auto& [id, b] : frames[k].bearings) {
      rays[id].first.push_back(rec->T[k]);
      rays[id].second.push_back(b);
    }
  }
  for (const auto& [id, r] : rays) {
    if (r.first.size() < 2 || (keep_existing && rec->points.count(id))) continue;
    const TriangulationResult tri = triangulate(r.first, r.second);
    if (tri.valid && tri.max_ray_angle_rad > kMinPointParallaxRad)
      rec->points[id] = tri.p_W;
    else
      rec->points.erase(id);
  }
}

// Joint refinement of the solved frames and the points; frame 0 is fixed and the reference
// frame's position stays on the unit sphere (the scale gauge).
void bundleAdjust(const std::vector<BearingFrame>& frames, int reference, double focal,
                  double loss_px, Reconstruction* rec) {
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  ceres::EigenQuaternionManifold quaternion;
  ceres::SphereManifold<3> sphere;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    if (!rec->solved[k]) continue;
    double* q = rec->T[k].q.coeffs().data();
    double* c = rec->T[k].p.data();
    for (const auto& [id, b] : frames[k].bearings) {
      auto it = rec->points.find(id);
      if (it == rec->points.end() || b.z() < 1e-6) continue;
      auto* cost = new ceres::AutoDiffCostFunction<BearingReprojection, 2, 4, 3, 3>(
          new BearingReprojection{b.head<2>() / b.z(), focal});
      problem.AddResidualBlock(cost, new ceres::HuberLoss(loss_px), q, c, it->second.data());
    }
    if (!problem.HasParameterBlock(q)) continue;
    problem.SetManifold(q, &quaternion);
    if (k == 0) {
      problem.SetParameterBlockConstant(q);
      problem.SetParameterBlockConstant(c);
    } else if (static_cast<int>(k) == reference) {
      problem.SetManifold(c, &sphere);
    }
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_SCHUR;
  so.max_num_iterations = 50;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  for (auto& T : rec->T) T.q.normalize();
}

// Camera pose from known points: translation linear for the given rotation, then a
// motion-only refinement of both. Returns the number of inliers.
int solvePnp(const BearingFrame& frame, const std::map<int, Vec3>& points, const Mat3& R_init,
             double focal, double thr_px, Pose* T_out, int* known = nullptr) {
  Mat3 A = Mat3::Zero();
  Vec3 rhs = Vec3::Zero();
  std::vector<std::pair<const Vec3*, const Vec3*>> used;
  for (const auto& [id, b] : frame.bearings) {
    auto it = points.find(id);
    if (it == points.end()) continue;
    // b x R^T (X - c) = 0  ->  [b]x R^T c = [b]x R^T X
    const Mat3 M = hat(b) * R_init.transpose();
    A += M.transpose() * M;
    rhs += M.transpose() * M * it->second;
    used.push_back({&it->second, &b});
  }
  if (known) *known = static_cast<int>(used.size());
  if (used.size() < 6) return 0;
  Pose T(R_init, A.ldlt().solve(rhs));
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  ceres::EigenQuaternionManifold quaternion;
  std::vector<Vec3> xs;
  xs.reserve(used.size());
  for (const auto& [x, b] : used) {
    xs.push_back(*x);
    auto* cost = new ceres::AutoDiffCostFunction<BearingReprojection, 2, 4, 3, 3>(
        new BearingReprojection{b->head<2>() / b->z(), focal});
    problem.AddResidualBlock(cost, new ceres::CauchyLoss(thr_px), T.q.coeffs().data(), T.p.data(),
                             xs.back().data());
    problem.SetParameterBlockConstant(xs.back().data());
  }
  problem.SetManifold(T.q.coeffs().data(), &quaternion);
  ceres::Solver::Options so;
  so.max_num_iterations = 30;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  T.q.normalize();
  int inliers = 0;
  for (const auto& [x, b] : used)
    if (reprojectionErrorPx(T, *x, *b, focal) < thr_px) ++inliers;
  *T_out = T;
  return inliers;
}

}  // namespace

double medianParallax(const BearingFrame& a, const BearingFrame& b, int* common) {
  // The rotation that best explains the motion of the bearings (Wahba / Kabsch): parallax is
  // what it leaves, so a biased gyro cannot fake parallax and pure rotation gives ~0.
  std::vector<std::pair<Vec3, Vec3>> pairs;
  Mat3 M = Mat3::Zero();
  for (const auto& [id, xa] : a.bearings) {
    auto it = b.bearings.find(id);
    if (it == b.bearings.end()) continue;
    pairs.push_back({xa, it->second});
    M += xa * it->second.transpose();
  }
  if (common) *common = static_cast<int>(pairs.size());
  if (pairs.size() < 3) return 0.0;
  const Eigen::JacobiSVD<Mat3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Mat3 R_ab = svd.matrixU() * D * svd.matrixV().transpose();
  std::vector<double> angles;
  for (const auto& [xa, xb] : pairs)
    angles.push_back(std::acos(std::clamp(xa.dot(R_ab * xb), -1.0, 1.0)));
  std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
  return angles[angles.size() / 2];
}

SfmResult reconstructUpToScale(const std::vector<BearingFrame>& frames,
                               const std::vector<Mat3>& R_C0C_prior, double focal_px,
                               const SfmOptions& options) {
  SfmResult out;
  const int n = static_cast<int>(frames.size());
  if (n < 2 || R_C0C_prior.size() != frames.size()) {
    out.reason = "fewer than two frames";
    return out;
  }
  // Reference frame: the most parallax with the first among frames sharing enough tracks.
  for (int k = 1; k < n; ++k) {
    int common = 0;
    const double par = medianParallax(frames[0], frames[k], &common);
    if (common >= options.min_common_tracks && par > out.reference_parallax_rad) {
      out.reference_parallax_rad = par;
      out.reference_frame = k;
    }
  }
  if (out.reference_frame < 0) {
    out.reason = "fewer than " + std::to_string(options.min_common_tracks) +
                 " tracks shared with the first frame";
    return out;
  }
  if (out.reference_parallax_rad < options.min_parallax_rad) {
    out.reason = "insufficient parallax (" +
                 std::to_string(out.reference_parallax_rad * 180.0 / M_PI) + " deg)";
    return out;
  }
  const int l = out.reference_frame;
  std::vector<Correspondence> cs;
  for (const auto& [id, x0] : frames[0].bearings) {
    auto it = frames[l].bearings.find(id);
    if (it != frames[l].bearings.end()) cs.push_back({id, x0, it->second});
  }
  const double thr = options.inlier_threshold_px / focal_px;
  const TwoView tv = twoViewGeometry(cs, R_C0C_prior[l], thr, options);
  if (static_cast<int>(tv.inliers.size()) < options.min_common_tracks) {
    out.reason = "two-view geometry: only " + std::to_string(tv.inliers.size()) + " inliers";
    return out;
  }

  Reconstruction rec;
  rec.T.assign(n, Pose());
  rec.solved.assign(n, false);
  rec.solved[0] = rec.solved[l] = true;
  rec.T[l] = Pose(tv.R, tv.t.normalized());
  for (int i : tv.inliers) {
    const TriangulationResult tri = triangulate({rec.T[0], rec.T[l]}, {cs[i].x0, cs[i].x1});
    if (tri.valid) rec.points[cs[i].id] = tri.p_W;
  }
  if (static_cast<int>(rec.points.size()) < options.min_pnp_points) {
    out.reason = "two-view triangulation: only " + std::to_string(rec.points.size()) + " points";
    return out;
  }
  bundleAdjust(frames, l, focal_px, options.inlier_threshold_px, &rec);

  // The other frames in time order, each seeded by the gyro rotation relative to the nearest
  // solved frame (so a gyro bias drifts over a few frames only).
  for (int k = 1; k < n; ++k) {
    if (rec.solved[k]) continue;
    int j = -1;
    for (int d = 1; d < n && j < 0; ++d) {
      if (k - d >= 0 && rec.solved[k - d])
        j = k - d;
      else if (k + d < n && rec.solved[k + d])
        j = k + d;
    }
    const Mat3 R_init = rec.T[j].R() * R_C0C_prior[j].transpose() * R_C0C_prior[k];
    Pose T;
    int known = 0;
    const int inliers = solvePnp(frames[k], rec.points, R_init, focal_px,
                                 2.0 * options.inlier_threshold_px, &T, &known);
    if (inliers < options.min_pnp_points) {
      out.reason = "pose of frame " + std::to_string(k) + ": " + std::to_string(inliers) +
                   " inliers of " + std::to_string(known) + " known points (" +
                   std::to_string(frames[k].bearings.size()) + " tracks)";
      return out;
    }
    rec.T[k] = T;
    rec.solved[k] = true;
    // Re-triangulate with every view so early, low-parallax points do not drift the chain.
    triangulateAll(frames, &rec, /*keep_existing=*/false);
  }

  // Global refinement, then drop outlier observations' points and refine again.
  triangulateAll(frames, &rec, /*keep_existing=*/true);
  bundleAdjust(frames, l, focal_px, options.inlier_threshold_px, &rec);
  for (auto it = rec.points.begin(); it != rec.points.end();) {
    bool bad = false;
    for (int k = 0; k < n && !bad; ++k) {
      auto b = frames[k].bearings.find(it->first);
      if (b != frames[k].bearings.end() &&
          reprojectionErrorPx(rec.T[k], it->second, b->second, focal_px) >
              2.0 * options.inlier_threshold_px)
        bad = true;
    }
    it = bad ? rec.points.erase(it) : std::next(it);
  }
  bundleAdjust(frames, l, focal_px, options.inlier_threshold_px, &rec);

  double sq = 0.0;
  for (int k = 0; k < n; ++k)
    for (const auto& [id, b] : frames[k].bearings) {
      auto it = rec.points.find(id);
      if (it == rec.points.end()) continue;
      const double e = reprojectionErrorPx(rec.T[k], it->second, b, focal_px);
      if (e > 2.0 * options.inlier_threshold_px) continue;
      sq += e * e;
      ++out.inlier_observations;
    }
  out.rms_reprojection_px = out.inlier_observations ? std::sqrt(sq / out.inlier_observations) : 0;
  if (static_cast<int>(rec.points.size()) < options.min_landmarks) {
    out.reason = "only " + std::to_string(rec.points.size()) + " landmarks after refinement";
    return out;
  }
  out.T_C0C = rec.T;
  out.points_C0 = rec.points;
  out.success = true;
  return out;
}

}  // namespace hdvio::vi_init
