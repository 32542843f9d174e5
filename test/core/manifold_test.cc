#include "hdvio/core/manifolds.h"

#include <ceres/manifold_test_utils.h>
#include <gtest/gtest.h>

#include <random>

#include "hdvio/core/lie.h"

namespace hdvio {
namespace {

Eigen::Matrix<double, 7, 1> randomPose(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, 7, 1> x;
  const Quat q = quatExp(Vec3(n(rng), n(rng), n(rng)));
  x << n(rng), n(rng), n(rng), q.coeffs();
  return x;
}

TEST(PoseManifold, CeresInvariantsHold) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 0.3);
  using namespace ceres;  // the invariant macro uses unqualified ceres names
  PoseManifold manifold;
  for (int i = 0; i < 20; ++i) {
    const Eigen::Matrix<double, 7, 1> x = randomPose(rng);
    Eigen::Matrix<double, 7, 1> y = randomPose(rng);
    // Minus returns the shortest rotation, so Plus(x, Minus(y, x)) reproduces y only up to the
    // quaternion sign; pick the representative of y in x's hemisphere.
    if (x.tail<4>().dot(y.tail<4>()) < 0) y.tail<4>() *= -1.0;
    Eigen::Matrix<double, 6, 1> delta;
    for (int k = 0; k < 6; ++k) delta[k] = n(rng);
    EXPECT_THAT_MANIFOLD_INVARIANTS_HOLD(manifold, x, delta, y, 1e-9);
  }
}

TEST(PoseManifold, MatchesPoseConvention) {
  std::mt19937 rng(8);
  const Eigen::Matrix<double, 7, 1> x = randomPose(rng);
  Vec6 d;
  d << 0.1, -0.2, 0.3, 0.05, -0.02, 0.04;
  Eigen::Matrix<double, 7, 1> out;
  PoseManifold().Plus(x.data(), d.data(), out.data());
  const Pose a(Quat(x[6], x[3], x[4], x[5]), x.head<3>());
  const Pose b = a.plus(d);
  EXPECT_LT((out.head<3>() - b.p).norm(), 1e-14);
  EXPECT_LT(Quat(out[6], out[3], out[4], out[5]).angularDistance(b.q), 1e-12);
}

TEST(PoseManifold, LiftInvertsPlusJacobian) {
  std::mt19937 rng(9);
  for (int i = 0; i < 10; ++i) {
    const Eigen::Matrix<double, 7, 1> x = randomPose(rng);
    Eigen::Matrix<double, 7, 6, Eigen::RowMajor> P;
    Eigen::Matrix<double, 6, 7, Eigen::RowMajor> L;
    PoseManifold().PlusJacobian(x.data(), P.data());
    PoseManifold::liftJacobian(x.data(), L.data());
    EXPECT_LT((L * P - Mat6::Identity()).norm(), 1e-12);
  }
}

}  // namespace
}  // namespace hdvio
