#include "hdvio/eval/alignment.h"

#include <Eigen/SVD>
#include <cmath>
#include <limits>

#include "hdvio/core/error.h"

namespace hdvio::eval {
namespace {

Mat3 rotZ(double theta) { return Eigen::AngleAxisd(theta, Vec3::UnitZ()).toRotationMatrix(); }

// rpg get_best_yaw: the theta maximizing trace(Rz(theta) * C).
double bestYaw(const Mat3& C) {
  const double A = C(0, 1) - C(1, 0);
  const double B = C(0, 0) + C(1, 1);
  return M_PI / 2.0 - std::atan2(B, A);
}

void requireMatchingSizes(const std::vector<Vec3>& est, const std::vector<Vec3>& ref) {
  if (est.size() != ref.size() || est.empty())
    throw InputError("", 0, "alignment needs the same, non-zero number of points");
}

}  // namespace

AlignmentType parseAlignmentType(const std::string& name) {
  if (name == "none") return AlignmentType::kNone;
  if (name == "posyaw") return AlignmentType::kPosYaw;
  if (name == "se3") return AlignmentType::kSE3;
  if (name == "sim3") return AlignmentType::kSim3;
  throw InputError("", 0, "unknown alignment '" + name + "' (none|posyaw|se3|sim3)");
}

std::string alignmentName(AlignmentType type) {
  switch (type) {
    case AlignmentType::kNone: return "none";
    case AlignmentType::kPosYaw: return "posyaw";
    case AlignmentType::kSE3: return "se3";
    case AlignmentType::kSim3: return "sim3";
  }
  return "?";
}

SimilarityTransform umeyamaAlignment(const std::vector<Vec3>& est, const std::vector<Vec3>& ref,
                                     bool with_scale) {
  requireMatchingSizes(est, ref);
  const double n = static_cast<double>(est.size());
  Vec3 mean_x = Vec3::Zero(), mean_y = Vec3::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) {
    mean_x += est[i];
    mean_y += ref[i];
  }
  mean_x /= n;
  mean_y /= n;
  double sigma_x = 0.0;
  Mat3 cov = Mat3::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) {
    sigma_x += (est[i] - mean_x).squaredNorm();
    cov += (ref[i] - mean_y) * (est[i] - mean_x).transpose();
  }
  sigma_x /= n;
  cov /= n;
  Eigen::JacobiSVD<Mat3> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Vec3 d = svd.singularValues();
  int rank = 0;
  for (int i = 0; i < 3; ++i) rank += d(i) > std::numeric_limits<double>::epsilon() ? 1 : 0;
  if (rank < 2)
    throw InputError("", 0, "degenerate alignment: the aligned positions are (nearly) collinear");
  Mat3 S = Mat3::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) S(2, 2) = -1.0;
  SimilarityTransform T;
  T.R = svd.matrixU() * S * svd.matrixV().transpose();
  T.s = with_scale ? (d.asDiagonal() * S).trace() / sigma_x : 1.0;
  T.t = mean_y - T.s * (T.R * mean_x);
  return T;
}

SimilarityTransform positionYawAlignment(const std::vector<Vec3>& est, const std::vector<Vec3>& ref) {
  requireMatchingSizes(est, ref);
  const double n = static_cast<double>(est.size());
  Vec3 mu_est = Vec3::Zero(), mu_ref = Vec3::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) {
    mu_est += est[i];
    mu_ref += ref[i];
  }
  mu_est /= n;
  mu_ref /= n;
  Mat3 C = Mat3::Zero();  // sum (est_i - mu_est)(ref_i - mu_ref)^T
  for (std::size_t i = 0; i < est.size(); ++i) C += (est[i] - mu_est) * (ref[i] - mu_ref).transpose();
  SimilarityTransform T;
  T.R = rotZ(bestYaw(C));
  T.t = mu_ref - T.R * mu_est;
  return T;
}

SimilarityTransform positionYawFromFirstPose(const Mat3& R_est, const Vec3& p_est,
                                             const Mat3& R_ref, const Vec3& p_ref) {
  SimilarityTransform T;
  T.R = rotZ(bestYaw(R_est * R_ref.transpose()));
  T.t = p_ref - T.R * p_est;
  return T;
}

SimilarityTransform computeAlignment(AlignmentType type, const Trajectory& ref,
                                     const Trajectory& est, int first_n) {
  if (type == AlignmentType::kNone) return SimilarityTransform();
  const std::size_t n = first_n <= 0 ? est.size() : std::min<std::size_t>(first_n, est.size());
  if (n == 0) throw InputError(est.source, 0, "nothing to align");
  const std::vector<Vec3> est_p(est.p.begin(), est.p.begin() + n);
  const std::vector<Vec3> ref_p(ref.p.begin(), ref.p.begin() + n);
  switch (type) {
    case AlignmentType::kPosYaw:
      if (n == 1) return positionYawFromFirstPose(est.R[0], est.p[0], ref.R[0], ref.p[0]);
      return positionYawAlignment(est_p, ref_p);
    case AlignmentType::kSE3: return umeyamaAlignment(est_p, ref_p, false);
    case AlignmentType::kSim3: return umeyamaAlignment(est_p, ref_p, true);
    case AlignmentType::kNone: break;
  }
  return SimilarityTransform();
}

Trajectory applyAlignment(const SimilarityTransform& T, const Trajectory& est) {
  Trajectory out = est;
  for (std::size_t i = 0; i < out.size(); ++i) {
    out.p[i] = T.apply(est.p[i]);
    out.R[i] = T.R * est.R[i];
  }
  for (Vec3& v : out.v) v = T.s * (T.R * v);
  return out;
}

}  // namespace hdvio::eval
