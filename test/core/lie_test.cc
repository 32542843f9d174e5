#include "hdvio/core/lie.h"

#include <gtest/gtest.h>

#include <random>

namespace hdvio {
namespace {

Vec3 randomVec(std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, scale);
  return Vec3(n(rng), n(rng), n(rng));
}

TEST(Lie, ExpLogRoundTrip) {
  std::mt19937 rng(1);
  for (int i = 0; i < 200; ++i) {
    Vec3 phi = randomVec(rng, 1.0);
    if (phi.norm() > 3.0) phi *= 3.0 / phi.norm();
    EXPECT_LT((so3Log(so3Exp(phi)) - phi).norm(), 1e-10);
    EXPECT_LT((quatLog(quatExp(phi)) - phi).norm(), 1e-10);
    EXPECT_LT((quatExp(phi).toRotationMatrix() - so3Exp(phi)).norm(), 1e-12);
  }
  // Tiny and near-pi angles.
  const Vec3 tiny(1e-12, -2e-12, 3e-12);
  EXPECT_LT((so3Log(so3Exp(tiny)) - tiny).norm(), 1e-18);
  const Vec3 near_pi = Vec3(0.3, -0.5, 0.8).normalized() * (M_PI - 1e-6);
  EXPECT_LT((so3Log(so3Exp(near_pi)) - near_pi).norm(), 1e-8);
}

TEST(Lie, RightJacobianFirstOrder) {
  std::mt19937 rng(2);
  for (int i = 0; i < 50; ++i) {
    const Vec3 phi = randomVec(rng, 0.8);
    const Vec3 d = randomVec(rng, 1e-6);
    // Exp(phi + d) = Exp(phi) Exp(Jr d) + O(d^2)
    const Vec3 lhs = so3Log(so3Exp(phi).transpose() * so3Exp(phi + d));
    EXPECT_LT((lhs - rightJacobian(phi) * d).norm(), 1e-11);
    const Vec3 lhs_left = so3Log(so3Exp(phi + d) * so3Exp(phi).transpose());
    EXPECT_LT((lhs_left - leftJacobian(phi) * d).norm(), 1e-11);
    EXPECT_LT((rightJacobian(phi) * rightJacobianInverse(phi) - Mat3::Identity()).norm(), 1e-10);
    EXPECT_LT((leftJacobian(phi) * leftJacobianInverse(phi) - Mat3::Identity()).norm(), 1e-10);
  }
}

TEST(Lie, Se3ExpLogAndAdjoint) {
  std::mt19937 rng(3);
  for (int i = 0; i < 50; ++i) {
    Vec6 xi;
    xi << randomVec(rng, 2.0), randomVec(rng, 0.7);
    const Pose T = se3Exp(xi);
    EXPECT_LT((se3Log(T) - xi).norm(), 1e-9);
    // Matrix exponential reference by scaling and squaring of the 4x4 twist matrix.
    Mat4 X = Mat4::Zero();
    X.topLeftCorner<3, 3>() = hat(xi.tail<3>());
    X.topRightCorner<3, 1>() = xi.head<3>();
    Mat4 E = Mat4::Identity(), term = Mat4::Identity();
    const Mat4 Xs = X / 1024.0;
    for (int k = 1; k < 20; ++k) {
      term = term * Xs / k;
      E += term;
    }
    for (int k = 0; k < 10; ++k) E = E * E;
    EXPECT_LT((E - T.matrix()).norm(), 1e-8);
    // Adjoint: T Exp(xi2) T^-1 = Exp(Ad_T xi2)
    Vec6 xi2;
    xi2 << randomVec(rng, 0.5), randomVec(rng, 0.3);
    const Pose lhs = T * se3Exp(xi2) * T.inverse();
    const Pose rhs = se3Exp(se3Adjoint(T) * xi2);
    EXPECT_LT(lhs.minus(rhs).norm(), 1e-9);
  }
}

TEST(Lie, PosePlusMinusInverse) {
  std::mt19937 rng(4);
  for (int i = 0; i < 50; ++i) {
    const Pose a(quatExp(randomVec(rng, 1.0)), randomVec(rng, 3.0));
    Vec6 d;
    d << randomVec(rng, 0.5), randomVec(rng, 0.5);
    EXPECT_LT((a.plus(d).minus(a) - d).norm(), 1e-10);
    const Pose id = a * a.inverse();
    EXPECT_LT(id.p.norm(), 1e-12);
    EXPECT_NEAR(std::abs(id.q.w()), 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace hdvio
