#include "hdvio/backend/schur_marginalization.h"

#include <Eigen/LU>
#include <gtest/gtest.h>

#include <random>

#include "between_pose_factor.h"
#include "hdvio/core/ceres_bridge.h"
#include "hdvio/core/numerical_jacobian.h"

namespace hdvio {
namespace {
using symbols::X;

Pose randomPose(std::mt19937& rng, double scale = 1.0) {
  std::normal_distribution<double> n(0.0, scale);
  return Pose(quatExp(Vec3(n(rng), n(rng), n(rng))), Vec3(n(rng), n(rng), n(rng)));
}

// A small loop of poses with noisy relative measurements and an anchor on x0.
struct Loop {
  FactorGraph graph;
  Values values;
  int n = 5;
};

Loop makeLoop(bool anchored, std::mt19937& rng) {
  Loop loop;
  std::vector<Pose> truth;
  for (int k = 0; k < loop.n; ++k) truth.push_back(randomPose(rng, 2.0));
  const auto noise = NoiseModel::isotropic(6, 0.1);
  for (int k = 0; k < loop.n; ++k) {
    loop.values.insertPose(X(k), truth[k].plus(Vec6::Constant(0.01 * (k + 1))));
    const int j = (k + 1) % loop.n;
    loop.graph.add(std::make_shared<testing::BetweenPoseFactor>(
        X(k), X(j), truth[k].inverse() * truth[j], noise));
  }
  loop.graph.add(std::make_shared<testing::BetweenPoseFactor>(X(0), X(2),
                                                              truth[0].inverse() * truth[2], noise));
  if (anchored)
    loop.graph.add(std::make_shared<testing::PosePriorFactor>(X(0), truth[0], noise));
  return loop;
}

TEST(SchurMarginalization, PriorCovarianceEqualsMarginalCovariance) {
  std::mt19937 rng(3);
  const Loop loop = makeLoop(true, rng);
  const std::vector<Key> order{X(0), X(1), X(2), X(3), X(4)};
  const LinearSystem full = linearizeDense(loop.graph, loop.values, order);
  const Eigen::MatrixXd cov = full.H.inverse();
  const auto prior = marginalizeBySchurComplement(loop.graph, loop.values, {X(0), X(1)});
  ASSERT_TRUE(prior);
  ASSERT_EQ(prior->keys(), (std::vector<Key>{X(2), X(3), X(4)}));
  const Eigen::MatrixXd Hp = prior->jacobian().transpose() * prior->jacobian();
  const Eigen::MatrixXd cov_prior = Hp.inverse();
  EXPECT_LT((cov_prior - cov.bottomRightCorner(18, 18)).norm(), 1e-8 * cov.norm());
  // The gradient is preserved too: b' = b_r - H_rm H_mm^-1 b_m.
  const Eigen::MatrixXd Hmm = full.H.topLeftCorner(12, 12);
  const Eigen::VectorXd b_expected =
      full.b.tail(18) - full.H.bottomLeftCorner(18, 12) * Hmm.inverse() * full.b.head(12);
  const Eigen::VectorXd b_prior = prior->jacobian().transpose() * prior->residualAtLinearizationPoint();
  EXPECT_LT((b_prior - b_expected).norm(), 1e-8 * std::max(1.0, b_expected.norm()));
}

TEST(SchurMarginalization, PriorJacobianMatchesNumericAtLinearizationPoint) {
  std::mt19937 rng(4);
  const Loop loop = makeLoop(true, rng);
  const auto prior = marginalizeBySchurComplement(loop.graph, loop.values, {X(1)});
  ASSERT_TRUE(prior);
  EXPECT_LT(maxJacobianError(*prior, loop.values), 1e-6);
  // Its cost away from x0 agrees with the original graph's to second order.
  Values moved = loop.values;
  for (Key k : prior->keys()) moved.update(k, loop.values.plus(k, Eigen::VectorXd::Constant(6, 1e-3)));
  Eigen::VectorXd r;
  ASSERT_TRUE(prior->whitenedError(moved, &r));
  EXPECT_TRUE(r.allFinite());
}

TEST(SchurMarginalization, GaugeDirectionsStayUnobservable) {
  std::mt19937 rng(5);
  const Loop loop = makeLoop(false, rng);  // relative measurements only
  const auto prior = marginalizeBySchurComplement(loop.graph, loop.values, {X(0)});
  ASSERT_TRUE(prior);
  const Eigen::MatrixXd Hp = prior->jacobian().transpose() * prior->jacobian();
  // Global translation t and rotation w move each pose by dp = t - hat(p) w, dtheta = R^T w.
  Eigen::MatrixXd N = Eigen::MatrixXd::Zero(Hp.rows(), 6);
  int row = 0;
  for (Key k : prior->keys()) {
    const Pose T = loop.values.pose(k);
    N.block<3, 3>(row, 0) = Mat3::Identity();
    N.block<3, 3>(row, 3) = -hat(T.p);
    N.block<3, 3>(row + 3, 3) = T.R().transpose();
    row += 6;
  }
  EXPECT_LT((Hp * N).norm(), 1e-6 * Hp.norm());
  EXPECT_EQ(prior->jacobian().rows(), Hp.rows() - 6);  // rank deficient by exactly the gauge
}

TEST(SchurMarginalization, FreeVariableLeavesNoInformation) {
  std::mt19937 rng(6);
  FactorGraph chain;
  Values values;
  values.insertPose(X(0), randomPose(rng));
  values.insertPose(X(1), randomPose(rng));
  chain.add(std::make_shared<testing::BetweenPoseFactor>(X(0), X(1), randomPose(rng),
                                                         NoiseModel::isotropic(6, 0.1)));
  EXPECT_EQ(marginalizeBySchurComplement(chain, values, {X(0)}), nullptr);
}

// The own solver (schur_lm.h) takes a prior's Jacobian and J^T J as constants instead of
// evaluating them: that is exact (the tangent Jacobian away from x0 is J0) and it solves the
// window Ceres solves.
TEST(SchurMarginalization, PriorJacobianIsConstantAndTheOwnSolverAgreesWithCeres) {
  std::mt19937 rng(7);
  Loop loop = makeLoop(true, rng);
  const auto prior = marginalizeBySchurComplement(loop.graph, loop.values, {X(0), X(1)});
  ASSERT_TRUE(prior);
  const Factor::ConstantJacobian c = prior->constantJacobian();
  ASSERT_TRUE(c.J && c.JtJ);
  EXPECT_LT((*c.JtJ - c.J->transpose() * *c.J).norm(), 1e-12 * c.JtJ->norm());
  Values moved = loop.values;
  for (Key k : prior->keys()) moved.update(k, loop.values.plus(k, 0.2 * Eigen::VectorXd::Random(6)));
  Linearization lin;
  ASSERT_TRUE(prior->linearize(moved, &lin));
  for (std::size_t i = 0; i < prior->keys().size(); ++i)
    EXPECT_LT((lin.jacobians[i] - c.J->middleCols(6 * static_cast<int>(i), 6)).norm(), 1e-9 * c.J->norm());

  // What is left of the loop after x0 and x1 went into the prior, solved from a moved start.
  FactorGraph rest;
  rest.add(prior);
  for (const auto& f : loop.graph) {
    bool keeps = true;
    for (Key k : f->keys()) keeps = keeps && k != X(0) && k != X(1);
    if (keeps) rest.add(f);
  }
  Values start = moved.subset(prior->keys());
  OptimizerOptions o;
  o.linear_solver = ceres::DENSE_SCHUR;
  o.max_iterations = 100;
  o.function_tolerance = 1e-14;
  Values by_ceres = start, own = start;
  ASSERT_TRUE(optimize(rest, &by_ceres, o).usable);
  o.optimizer = OptimizerOptions::Optimizer::kSchurLm;
  ASSERT_TRUE(optimize(rest, &own, o).usable);
  for (Key k : prior->keys()) {
    EXPECT_LT(own.minus(k, by_ceres).cwiseAbs().maxCoeff(), 1e-7) << k.str();
    EXPECT_GT(own.minus(k, start).norm(), 1e-2) << k.str();  // the solve moved it
  }
}

}  // namespace
}  // namespace hdvio
