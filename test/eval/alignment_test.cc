// Alignment checked against independent closed forms: Horn's quaternion method (1987) for
// SE(3)/Sim(3) and the 2-D Procrustes angle for position+yaw.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "hdvio/core/error.h"
#include "hdvio/eval/alignment.h"

namespace hdvio::eval {
namespace {

struct PointSets {
  std::vector<Vec3> est, ref;
};

// ref = s R est + t + noise, est spread like a flight (a few metres, some height change).
PointSets makePoints(double s, const Mat3& R, const Vec3& t, double noise, unsigned seed, int n = 200) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  PointSets ps;
  for (int i = 0; i < n; ++i) {
    const double a = 0.05 * i;
    const Vec3 x(3.0 * std::cos(a) + 0.3 * gauss(rng), 2.0 * std::sin(1.3 * a) + 0.3 * gauss(rng),
                 1.0 + 0.5 * std::sin(0.7 * a));
    ps.est.push_back(x);
    ps.ref.push_back(s * R * x + t + noise * Vec3(gauss(rng), gauss(rng), gauss(rng)));
  }
  return ps;
}

// Horn, "Closed-form solution of absolute orientation using unit quaternions", with the scale
// that minimizes the same (asymmetric) cost as Umeyama given the rotation.
SimilarityTransform horn(const std::vector<Vec3>& est, const std::vector<Vec3>& ref, bool with_scale) {
  Vec3 me = Vec3::Zero(), mr = Vec3::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) {
    me += est[i];
    mr += ref[i];
  }
  me /= est.size();
  mr /= est.size();
  Mat3 S = Mat3::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) S += (est[i] - me) * (ref[i] - mr).transpose();
  const double xx = S(0, 0), xy = S(0, 1), xz = S(0, 2), yx = S(1, 0), yy = S(1, 1), yz = S(1, 2),
               zx = S(2, 0), zy = S(2, 1), zz = S(2, 2);
  Eigen::Matrix4d N;
  N << xx + yy + zz, yz - zy, zx - xz, xy - yx,  //
      yz - zy, xx - yy - zz, xy + yx, zx + xz,   //
      zx - xz, xy + yx, -xx + yy - zz, yz + zy,  //
      xy - yx, zx + xz, yz + zy, -xx - yy + zz;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(N);
  const Eigen::Vector4d v = eig.eigenvectors().col(3);  // largest eigenvalue
  SimilarityTransform T;
  T.R = Quat(v(0), v(1), v(2), v(3)).normalized().toRotationMatrix();
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    num += (ref[i] - mr).dot(T.R * (est[i] - me));
    den += (est[i] - me).squaredNorm();
  }
  T.s = with_scale ? num / den : 1.0;
  T.t = mr - T.s * T.R * me;
  return T;
}

Mat3 someRotation() {
  return (Eigen::AngleAxisd(0.7, Vec3::UnitZ()) * Eigen::AngleAxisd(-0.3, Vec3::UnitY()) *
          Eigen::AngleAxisd(0.2, Vec3::UnitX())).toRotationMatrix();
}

void expectSame(const SimilarityTransform& a, const SimilarityTransform& b, double tol) {
  EXPECT_NEAR(a.s, b.s, tol);
  EXPECT_LT((a.R - b.R).cwiseAbs().maxCoeff(), tol);
  EXPECT_LT((a.t - b.t).cwiseAbs().maxCoeff(), tol);
}

TEST(EvalSim3Alignment, RecoversExactTransformWithoutNoise) {
  const PointSets ps = makePoints(1.7, someRotation(), Vec3(1, -2, 3), 0.0, 1);
  const SimilarityTransform T = umeyamaAlignment(ps.est, ps.ref, true);
  expectSame(T, SimilarityTransform{1.7, someRotation(), Vec3(1, -2, 3)}, 1e-10);
}

TEST(EvalSim3Alignment, MatchesHornClosedFormWithNoise) {
  const PointSets ps = makePoints(0.8, someRotation(), Vec3(4, 0.5, -1), 0.2, 2);
  const SimilarityTransform T = umeyamaAlignment(ps.est, ps.ref, true);
  expectSame(T, horn(ps.est, ps.ref, true), 1e-9);
  EXPECT_GT(std::abs(T.s - 0.8), 1e-5);  // noise moved it: the comparison is not trivial
}

TEST(EvalSe3Alignment, MatchesHornClosedFormWithNoise) {
  const PointSets ps = makePoints(1.0, someRotation(), Vec3(-3, 2, 0.5), 0.2, 3);
  const SimilarityTransform T = umeyamaAlignment(ps.est, ps.ref, false);
  EXPECT_DOUBLE_EQ(T.s, 1.0);
  expectSame(T, horn(ps.est, ps.ref, false), 1e-9);
}

TEST(EvalSim3Alignment, CollinearPointsAreRejected) {
  std::vector<Vec3> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(i, 2.0 * i, 0.0);
  EXPECT_THROW(umeyamaAlignment(line, line, true), InputError);
}

// Independent 2-D closed form: yaw = atan2(sum cross, sum dot) of centred xy, z by the means.
SimilarityTransform procrustesYaw(const std::vector<Vec3>& est, const std::vector<Vec3>& ref) {
  Vec3 me = Vec3::Zero(), mr = Vec3::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) {
    me += est[i];
    mr += ref[i];
  }
  me /= est.size();
  mr /= est.size();
  double cross = 0.0, dot = 0.0;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const Vec3 e = est[i] - me, r = ref[i] - mr;
    cross += e.x() * r.y() - e.y() * r.x();
    dot += e.x() * r.x() + e.y() * r.y();
  }
  SimilarityTransform T;
  T.R = Eigen::AngleAxisd(std::atan2(cross, dot), Vec3::UnitZ()).toRotationMatrix();
  T.t = mr - T.R * me;
  return T;
}

double cost(const SimilarityTransform& T, const PointSets& ps) {
  double c = 0.0;
  for (std::size_t i = 0; i < ps.est.size(); ++i) c += (ps.ref[i] - T.apply(ps.est[i])).squaredNorm();
  return c;
}

TEST(EvalPosYawAlignment, RecoversYawAndTranslationWithoutNoise) {
  const Mat3 Rz = Eigen::AngleAxisd(2.5, Vec3::UnitZ()).toRotationMatrix();
  const PointSets ps = makePoints(1.0, Rz, Vec3(0.3, -4, 1.2), 0.0, 4);
  expectSame(positionYawAlignment(ps.est, ps.ref), SimilarityTransform{1.0, Rz, Vec3(0.3, -4, 1.2)}, 1e-10);
}

TEST(EvalPosYawAlignment, MatchesProcrustesClosedFormAndIsOptimal) {
  // Data with a small roll the 4-DoF model cannot explain, plus noise.
  const Mat3 R = (Eigen::AngleAxisd(-1.1, Vec3::UnitZ()) * Eigen::AngleAxisd(0.05, Vec3::UnitX())).toRotationMatrix();
  const PointSets ps = makePoints(1.0, R, Vec3(2, 1, -0.5), 0.1, 5);
  const SimilarityTransform T = positionYawAlignment(ps.est, ps.ref);
  expectSame(T, procrustesYaw(ps.est, ps.ref), 1e-10);
  EXPECT_NEAR(T.R(2, 2), 1.0, 1e-15);  // a pure yaw
  for (double d : {-1e-3, 1e-3}) {
    SimilarityTransform other = T;
    other.R = Eigen::AngleAxisd(d, Vec3::UnitZ()).toRotationMatrix() * T.R;
    Vec3 me = Vec3::Zero(), mr = Vec3::Zero();
    for (std::size_t i = 0; i < ps.est.size(); ++i) {
      me += ps.est[i];
      mr += ps.ref[i];
    }
    other.t = (mr - other.R * me) / ps.est.size();
    EXPECT_GT(cost(other, ps), cost(T, ps));
  }
}

TEST(EvalPosYawAlignment, SinglePoseVariantUsesFirstOrientation) {
  const double yaw = 0.9;
  const Mat3 Rz = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  const Mat3 R_est = someRotation();
  const Mat3 R_ref = Rz * R_est;
  const SimilarityTransform T = positionYawFromFirstPose(R_est, Vec3(1, 2, 3), R_ref, Vec3(-1, 0, 2));
  EXPECT_LT((T.R - Rz).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((T.apply(Vec3(1, 2, 3)) - Vec3(-1, 0, 2)).norm(), 1e-12);
}

TEST(EvalApplyAlignment, TransformsPosesAndVelocities) {
  Trajectory est;
  est.push(0, Vec3(1, 0, 0), Mat3::Identity());
  est.v.emplace_back(1, 0, 0);
  const SimilarityTransform T{2.0, Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix(), Vec3(0, 0, 1)};
  const Trajectory out = applyAlignment(T, est);
  EXPECT_LT((out.p[0] - Vec3(0, 2, 1)).norm(), 1e-12);
  EXPECT_LT((out.v[0] - Vec3(0, 2, 0)).norm(), 1e-12);
  EXPECT_LT((out.R[0] - T.R).norm(), 1e-12);
}

TEST(EvalComputeAlignment, UsesOnlyTheFirstNPoses) {
  // The first 50 poses are exact, the rest are shifted: aligning on the first 50 ignores them.
  const Mat3 Rz = Eigen::AngleAxisd(0.4, Vec3::UnitZ()).toRotationMatrix();
  PointSets ps = makePoints(1.0, Rz, Vec3(1, 1, 0), 0.0, 6);
  Trajectory ref, est;
  for (std::size_t i = 0; i < ps.est.size(); ++i) {
    est.push(static_cast<Timestamp>(i), ps.est[i], Mat3::Identity());
    ref.push(static_cast<Timestamp>(i), ps.ref[i] + (i >= 50 ? Vec3(5, 0, 0) : Vec3::Zero()), Rz);
  }
  const SimilarityTransform T = computeAlignment(AlignmentType::kPosYaw, ref, est, 50);
  expectSame(T, SimilarityTransform{1.0, Rz, Vec3(1, 1, 0)}, 1e-10);
  const SimilarityTransform all = computeAlignment(AlignmentType::kPosYaw, ref, est, -1);
  EXPECT_GT((all.t - Vec3(1, 1, 0)).norm(), 1.0);
}

}  // namespace
}  // namespace hdvio::eval
