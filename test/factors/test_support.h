#pragma once
// Shared helpers for the factor tests: a smooth analytic flight and manifold numerical
// Jacobians.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <type_traits>

#include "hdvio/core/factor.h"
#include "hdvio/core/lie.h"
#include "hdvio/core/numerical_jacobian.h"
#include "hdvio/core/sequence.h"
#include "hdvio/core/values.h"
#include "hdvio/factors/dynamics_factors.h"

namespace hdvio::test {

// A smooth trajectory with closed-form derivatives: p(t) sinusoids, R(t) = Exp(phi(t)),
// body rate w = Jr(phi) phi_dot, specific force a = R^T (p_ddot - g).
struct AnalyticFlight {
  Vec3 p(double t) const { return Vec3(2.0 * std::sin(1.3 * t), 1.5 * std::cos(0.7 * t), 0.5 * std::sin(2.0 * t)); }
  Vec3 v(double t) const { return Vec3(2.6 * std::cos(1.3 * t), -1.05 * std::sin(0.7 * t), 1.0 * std::cos(2.0 * t)); }
  Vec3 acc(double t) const { return Vec3(-3.38 * std::sin(1.3 * t), -0.735 * std::cos(0.7 * t), -2.0 * std::sin(2.0 * t)); }
  Vec3 phi(double t) const { return Vec3(0.3 * std::sin(1.1 * t), 0.2 * std::cos(0.9 * t), 0.8 * t); }
  Vec3 phiDot(double t) const { return Vec3(0.33 * std::cos(1.1 * t), -0.18 * std::sin(0.9 * t), 0.8); }
  Mat3 R(double t) const { return so3Exp(phi(t)); }
  Vec3 gyro(double t) const { return rightJacobian(phi(t)) * phiDot(t); }
  Vec3 specificForce(double t) const { return R(t).transpose() * (acc(t) - gravityWorld()); }
};

inline std::vector<ImuSample> sampleImu(const AnalyticFlight& f, double rate_hz, double t_end,
                                        const Vec3& bg = Vec3::Zero(), const Vec3& ba = Vec3::Zero()) {
  std::vector<ImuSample> out;
  const int n = static_cast<int>(std::ceil(t_end * rate_hz));
  for (int k = 0; k <= n; ++k) {
    const double t = k / rate_hz;
    out.push_back({fromSeconds(t), f.gyro(t) + bg, f.specificForce(t) + ba});
  }
  return out;
}

// Central differences of the whitened residual along each tangent coordinate (Values::plus),
// compared with Factor::linearize. Tolerance is relative to the block's largest entry.
inline void expectJacobiansMatchNumerical(const Factor& factor, const Values& values,
                                          double tol = 1e-6, double h = 1e-6) {
  Linearization lin;
  ASSERT_TRUE(factor.linearize(values, &lin));
  ASSERT_TRUE(lin.residual.allFinite());
  const std::vector<Eigen::MatrixXd> numeric = numericalJacobians(factor, values, h);
  for (std::size_t i = 0; i < factor.keys().size(); ++i) {
    const Key key = factor.keys()[i];
    const Eigen::MatrixXd& numerical = numeric[i];
    const Eigen::MatrixXd& analytic = lin.jacobians[i];
    ASSERT_EQ(analytic.rows(), numerical.rows());
    ASSERT_EQ(analytic.cols(), numerical.cols());
    const double scale = std::max(1.0, numerical.cwiseAbs().maxCoeff());
    EXPECT_LE((analytic - numerical).cwiseAbs().maxCoeff(), tol * scale)
        << "key " << key << "\nanalytic\n" << analytic << "\nnumerical\n" << numerical;
  }
}

inline Vec3 randomVec3(std::mt19937& rng, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  return Vec3(n(rng), n(rng), n(rng));
}

inline Pose randomPose(std::mt19937& rng) {
  return Pose(quatExp(randomVec3(rng, 1.5)), randomVec3(rng, 3.0));
}

// Random measurements, then states near (not at) what they predict, so residuals are moderate
// and every bias-correction term is active.
inline std::vector<DynamicsStep> randomSteps(std::mt19937& rng, int n) {
  std::vector<DynamicsStep> steps(n);
  for (auto& s : steps) {
    s.dt = 0.005;
    s.gyro = randomVec3(rng, 1.0);
    s.accel = Vec3(0, 0, 9.81) + randomVec3(rng, 2.0);
    s.thrust = Vec3(0, 0, 9.0) + randomVec3(rng, 0.5);
    s.residual_force = randomVec3(rng, 0.3);
  }
  return steps;
}

inline Values randomStates(std::mt19937& rng, const Mat3& dR) {
  using namespace symbols;
  Values v;
  const Pose Ti = randomPose(rng);
  v.insertPose(X(0), Ti);
  v.insertPose(X(1), Pose(Mat3(Ti.R() * dR * so3Exp(randomVec3(rng, 0.3))), Ti.p + randomVec3(rng, 1.0)));
  for (int k = 0; k < 2; ++k) {
    v.insertVector(V(k), randomVec3(rng, 2.0));
    v.insertVector(F(k), randomVec3(rng, 1.0));
    Eigen::VectorXd b(6);
    b << randomVec3(rng, 0.05), randomVec3(rng, 0.2);
    v.insertVector(B(k), b);
  }
  return v;
}

// Each dynamics factor with the keys of its model (HDVIO's also has F_j).
template <class Factor>
std::unique_ptr<Factor> makeDynamics(std::shared_ptr<const PreintegratedThrust> pit,
                                     const DynamicsFactorParams& params) {
  if constexpr (std::is_same_v<Factor, HdvioDynamicsFactor>)
    return std::make_unique<Factor>(symbols::X(0), symbols::V(0), symbols::F(0), symbols::X(1), symbols::V(1),
                                     symbols::F(1), symbols::B(0), pit, params);
  else
    return std::make_unique<Factor>(symbols::X(0), symbols::V(0), symbols::F(0), symbols::X(1), symbols::V(1),
                                     symbols::B(0), pit, params);
}

}  // namespace hdvio::test
