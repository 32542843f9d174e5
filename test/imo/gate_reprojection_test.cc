// Gate-corner reprojection for the IMO filter: analytic Jacobians against central differences
// (distorted camera, tilted mount, random poses), the stacked frame measurement, and the
// generic EKF update (Kalman algebra, Joseph form, chi-square gate with m dof).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "hdvio/backend/imo/gate_reprojection.h"
#include "hdvio/backend/imo/imo_filter.h"

namespace hdvio::imo {
namespace {

CameraModel distortedCamera() {
  return CameraModel(752, 480, 458.654, 457.296, 367.215, 248.375, DistortionModel::kRadialTangential,
                     {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
}

// Forward-looking camera with 30 deg uptilt and an offset (as in bench_race_v15.yaml).
Pose tiltedMount() {
  Mat3 R;
  R << 0.0, 0.5, 0.8660254037844387, -1.0, 0.0, 0.0, 0.0, -0.8660254037844387, 0.5;
  return Pose(R, Vec3(0.05, 0.01, -0.02));
}

struct Scenario {
  Mat3 R;
  Vec3 p;
  Vec3 corner;
};

// A random body pose and a corner 2..12 m in front of its camera, near the optical axis.
Scenario randomScenario(std::mt19937_64& rng, const Pose& T_BC) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Scenario s;
  s.R = so3Exp(Vec3(0.5 * u(rng), 0.5 * u(rng), 3.0 * u(rng)));
  s.p = Vec3(5.0 * u(rng), 5.0 * u(rng), 2.0 + u(rng));
  const Vec3 p_C(1.5 * u(rng), 1.0 * u(rng), 7.0 + 5.0 * u(rng));
  s.corner = s.R * (T_BC * p_C) + s.p;
  return s;
}

TEST(GateReprojection, JacobianMatchesCentralDifferences) {
  const CameraModel camera = distortedCamera();
  const Pose T_BC = tiltedMount();
  std::mt19937_64 rng(7);
  double worst = 0.0;
  for (int trial = 0; trial < 50; ++trial) {
    const Scenario s = randomScenario(rng, T_BC);
    Vec2 uv;
    Eigen::Matrix<double, 2, 6> J;
    ASSERT_TRUE(projectGateCorner(camera, T_BC, s.R, s.p, s.corner, &uv, &J));
    Eigen::Matrix<double, 2, 6> Jn;
    const double h = 1e-6;
    for (int i = 0; i < 6; ++i) {
      Vec6 d = Vec6::Zero();
      d[i] = h;
      Vec2 plus, minus;
      // dtheta perturbs on the right (R Exp(d)), dp additively in the world.
      ASSERT_TRUE(projectGateCorner(camera, T_BC, s.R * so3Exp(d.head<3>()), s.p + d.tail<3>(), s.corner, &plus));
      ASSERT_TRUE(projectGateCorner(camera, T_BC, s.R * so3Exp(-d.head<3>()), s.p - d.tail<3>(), s.corner, &minus));
      Jn.col(i) = (plus - minus) / (2.0 * h);
    }
    const double err = (J - Jn).cwiseAbs().maxCoeff() / std::max(1.0, Jn.cwiseAbs().maxCoeff());
    worst = std::max(worst, err);
    EXPECT_LT(err, 1e-6) << "trial " << trial << "\nanalytic\n" << J << "\nnumeric\n" << Jn;
  }
  RecordProperty("worst_relative_jacobian_error", std::to_string(worst));
}

TEST(GateReprojection, ProjectionMatchesTheMountGeometry) {
  // Identity body pose, default forward camera: a corner straight ahead lands on the principal point.
  const CameraModel camera(640, 480, 400.0, 400.0, 320.0, 240.0);
  Mat3 R_BC;
  R_BC.col(0) = Vec3(0.0, -1.0, 0.0);
  R_BC.col(1) = Vec3(0.0, 0.0, -1.0);
  R_BC.col(2) = Vec3(1.0, 0.0, 0.0);
  const Pose T_BC(R_BC, Vec3(0.1, 0.0, 0.0));
  Vec2 uv;
  ASSERT_TRUE(projectGateCorner(camera, T_BC, Mat3::Identity(), Vec3(1, 2, 3), Vec3(6.1, 2.0, 3.0), &uv));
  EXPECT_NEAR(uv.x(), 320.0, 1e-9);
  EXPECT_NEAR(uv.y(), 240.0, 1e-9);
  // 1 m to the left (world +y) and 0.5 m up at 6 m: u = cu - f / 6, v = cv - 0.5 f / 6.
  ASSERT_TRUE(projectGateCorner(camera, T_BC, Mat3::Identity(), Vec3(1, 2, 3), Vec3(7.1, 3.0, 3.5), &uv));
  EXPECT_NEAR(uv.x(), 320.0 - 400.0 / 6.0, 1e-9);
  EXPECT_NEAR(uv.y(), 240.0 - 200.0 / 6.0, 1e-9);
  // Behind the camera: no projection.
  EXPECT_FALSE(projectGateCorner(camera, T_BC, Mat3::Identity(), Vec3(1, 2, 3), Vec3(0.0, 2.0, 3.0), &uv));
}

TEST(GateReprojection, FrameMeasurementStacksCornersIntoTheErrorState) {
  const CameraModel camera = distortedCamera();
  const Pose T_BC = tiltedMount();
  std::mt19937_64 rng(3);
  const Scenario s = randomScenario(rng, T_BC);
  ImoNominalState x;
  x.R = s.R;
  x.p = s.p;
  std::vector<GateCornerObservation> obs;
  for (int k = 0; k < 4; ++k) {
    const Vec3 corner = s.corner + s.R * Vec3(0.0, 0.6 * (k % 2), 0.6 * (k / 2));
    Vec2 uv;
    ASSERT_TRUE(projectGateCorner(camera, T_BC, s.R, s.p, corner, &uv));
    obs.push_back({corner, uv + Vec2(0.5 * k, -0.25 * k)});
  }
  obs.push_back({s.p - s.R * (T_BC.R() * Vec3(0, 0, 5)), Vec2(1, 1)});  // behind the camera
  const int dim = kStateDim + 2 * kCloneDim;
  const GateFrameMeasurement m = gateFrameMeasurement(camera, T_BC, x, obs, dim);
  ASSERT_EQ(m.used, (std::vector<int>{0, 1, 2, 3}));
  ASSERT_EQ(m.residual.size(), 8);
  ASSERT_EQ(m.H.rows(), 8);
  ASSERT_EQ(m.H.cols(), dim);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR((m.residual.segment<2>(2 * k) - Vec2(0.5 * k, -0.25 * k)).norm(), 0.0, 1e-9);
  // Only dtheta (0..2) and dp (6..8) of the evolving state: velocity, biases and clones are 0.
  EXPECT_EQ(m.H.middleCols(3, 3).norm(), 0.0);
  EXPECT_EQ(m.H.middleCols(9, dim - 9).norm(), 0.0);
  // Linearization: residual after a small error-state step d is r - H d.
  VecX d = VecX::Zero(dim);
  d.segment<3>(0) = Vec3(1e-4, -2e-4, 1.5e-4);
  d.segment<3>(6) = Vec3(2e-3, -1e-3, 3e-3);
  ImoNominalState y = x;
  y.R = x.R * so3Exp(d.segment<3>(0));
  y.p = x.p + d.segment<3>(6);
  const GateFrameMeasurement m2 = gateFrameMeasurement(camera, T_BC, y, obs, dim);
  const VecX predicted = m.residual - m.H * d;
  EXPECT_LT((m2.residual - predicted).cwiseAbs().maxCoeff(), 1e-3 * (m2.residual - m.residual).cwiseAbs().maxCoeff());
}

TEST(GenericUpdate, MatchesTheKalmanEquationsAndKeepsTheCovarianceValid) {
  ImoFilterOptions o;
  ImoFilter f(o);
  ImoNominalState x0;
  x0.p = Vec3(1.0, 2.0, 3.0);
  f.initialize(x0);
  f.propagate(Vec3(0.1, -0.2, 0.3), Vec3(0.2, 0.1, 9.9), fromSeconds(0.05));
  f.addClone();
  f.propagate(Vec3(0.0, 0.1, 0.0), Vec3(0.0, 0.3, 9.7), fromSeconds(0.1));
  const MatX P = f.covariance();
  const int n = static_cast<int>(P.rows());
  ASSERT_EQ(n, kStateDim + kCloneDim);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  MatX H(5, n);
  for (int i = 0; i < H.size(); ++i) H.data()[i] = g(rng);
  VecX r(5);
  for (int i = 0; i < 5; ++i) r[i] = 0.1 * g(rng);
  const MatX R = 0.04 * MatX::Identity(5, 5);
  const MatX S = H * P * H.transpose() + R;
  const MatX K = P * H.transpose() * S.inverse();
  const MatX P_expected = (MatX::Identity(n, n) - K * H) * P;
  const VecX dx = K * r;
  const ImoNominalState before = f.state();
  ASSERT_EQ(f.updateGeneric(r, H, R), UpdateOutcome::kApplied);
  EXPECT_NEAR(f.lastMahalanobis(), r.dot(S.ldlt().solve(r)), 1e-9);
  const MatX P_after = f.covariance();
  EXPECT_LT((P_after - P_expected).cwiseAbs().maxCoeff(), 1e-9 * P.cwiseAbs().maxCoeff());
  EXPECT_LT((P_after - P_after.transpose()).cwiseAbs().maxCoeff(), 1e-15);
  // The clone starts as a copy of the evolving state, so P is nearly singular: PSD to round-off.
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatX>(P_after).eigenvalues().minCoeff(), -1e-12 * P.cwiseAbs().maxCoeff());
  EXPECT_LT((f.state().p - (before.p + dx.segment<3>(6))).norm(), 1e-12);
  EXPECT_LT((so3Log(before.R.transpose() * f.state().R) - dx.segment<3>(0)).norm(), 1e-12);
  EXPECT_THROW(f.updateGeneric(r, H.leftCols(n - 1), R), std::logic_error);
}

TEST(GenericUpdate, ChiSquareGateUsesTheMeasurementDimension) {
  ImoFilterOptions o;
  o.init_position_sigma = 1e-4;  // S ~ R = I: chi2 ~ r'r
  // Exact 99.9 % chi-square quantiles; the gate must accept 5 % below and reject 5 % above.
  const std::vector<std::pair<int, double>> quantiles = {{2, 13.816}, {8, 26.124}, {20, 45.315}};
  for (const auto& [m, q] : quantiles) {
    MatX H = MatX::Zero(m, kStateDim);
    for (int i = 0; i < m; ++i) H(i, 6 + i % 3) = 1.0;
    const MatX R = MatX::Identity(m, m);
    ImoFilter f(o);
    f.initialize(ImoNominalState{});
    EXPECT_EQ(f.updateGeneric(VecX::Constant(m, std::sqrt(0.95 * q / m)), H, R, 0.999), UpdateOutcome::kApplied) << m;
    f.initialize(ImoNominalState{});
    EXPECT_EQ(f.updateGeneric(VecX::Constant(m, std::sqrt(1.05 * q / m)), H, R, 0.999),
              UpdateOutcome::kRejectedByGate) << m;
    EXPECT_NEAR(f.lastMahalanobis(), 1.05 * q, 1e-3 * q);
    EXPECT_EQ(f.state().p, Vec3::Zero());  // rejected: untouched
    EXPECT_EQ(f.updateGeneric(VecX::Constant(m, std::sqrt(1.05 * q / m)), H, R), UpdateOutcome::kApplied) << m;
    EXPECT_NE(f.state().p, Vec3::Zero());
  }
}

}  // namespace
}  // namespace hdvio::imo
