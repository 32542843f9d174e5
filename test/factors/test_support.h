#pragma once
// Shared helpers for the factor tests: a smooth analytic flight and manifold numerical
// Jacobians.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hdvio/core/factor.h"
#include "hdvio/core/lie.h"
#include "hdvio/core/numerical_jacobian.h"
#include "hdvio/core/sequence.h"
#include "hdvio/core/values.h"

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

}  // namespace hdvio::test
