// A synthetic 3-D pose graph (a helix with odometry and loop closures) solved back to its
// ground truth through FactorGraph + Values + the Ceres bridge.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "between_pose_factor.h"
#include "hdvio/core/ceres_bridge.h"

namespace hdvio {
namespace {
using symbols::X;

std::vector<Pose> helix(int n) {
  std::vector<Pose> poses;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * M_PI * k / 20.0;
    const Vec3 p(5.0 * std::cos(a), 5.0 * std::sin(a), 0.1 * k);
    poses.emplace_back(quatExp(Vec3(0.1 * std::sin(a), 0.05, a + M_PI / 2)), p);
  }
  return poses;
}

Pose noisy(const Pose& T, std::mt19937& rng, double sp, double sr) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vec6 d;
  d << sp * n(rng), sp * n(rng), sp * n(rng), sr * n(rng), sr * n(rng), sr * n(rng);
  return T.plus(d);
}

double rmsPositionError(const std::vector<Pose>& truth, const Values& v) {
  double s = 0.0;
  for (std::size_t k = 0; k < truth.size(); ++k) s += (v.pose(X(k)).p - truth[k].p).squaredNorm();
  return std::sqrt(s / truth.size());
}

TEST(PoseGraph, LoopClosuresRecoverGroundTruth) {
  const int n = 60;
  const auto truth = helix(n);
  std::mt19937 rng(42);
  const double sp = 0.02, sr = 0.01;
  Eigen::VectorXd sigmas(6);
  sigmas << sp, sp, sp, sr, sr, sr;
  const auto noise = NoiseModel::diagonal(sigmas);

  FactorGraph graph;
  Values initial;
  graph.add(std::make_shared<testing::PosePriorFactor>(X(0), truth[0],
                                                       NoiseModel::isotropic(6, 1e-4)));
  initial.insertPose(X(0), truth[0]);
  Pose chained = truth[0];
  for (int k = 1; k < n; ++k) {
    const Pose z = noisy(truth[k - 1].inverse() * truth[k], rng, sp, sr);
    graph.add(std::make_shared<testing::BetweenPoseFactor>(X(k - 1), X(k), z, noise));
    chained = chained * z;
    initial.insertPose(X(k), chained);
  }
  int loops = 0;
  for (int k = 20; k < n; ++k) {  // same angle one turn earlier
    const Pose z = noisy(truth[k - 20].inverse() * truth[k], rng, sp, sr);
    graph.add(std::make_shared<testing::BetweenPoseFactor>(X(k - 20), X(k), z, noise));
    ++loops;
  }
  ASSERT_EQ(loops, 40);

  const double initial_rms = rmsPositionError(truth, initial);
  Values estimate = initial;
  const OptimizeResult result = optimize(graph, &estimate, OptimizerOptions());
  ASSERT_TRUE(result.usable) << result.summary.FullReport();
  const double final_rms = rmsPositionError(truth, estimate);
  std::printf("position rms: odometry %.4f m, optimized %.4f m\n", initial_rms, final_rms);
  EXPECT_LT(final_rms, 0.5 * initial_rms);
  // At the optimum the cost is that of the noise: chi2 with (6 * factors - 6 * n) dof.
  const double dof = 6.0 * (graph.size() - n);
  EXPECT_NEAR(2.0 * result.summary.final_cost / dof, 1.0, 0.35);

  // The estimation error is consistent with the information matrix of the solution:
  // NEES = e^T H e over all 6n tangent coordinates is chi2(6n) distributed.
  ceres::Problem problem(problemOptions());
  addToProblem(graph, &estimate, {}, &problem);
  std::vector<double*> blocks;
  for (int k = 0; k < n; ++k) blocks.push_back(estimate.data(X(k)));
  ceres::Problem::EvaluateOptions eval;
  eval.parameter_blocks = blocks;
  ceres::CRSMatrix crs;
  problem.Evaluate(eval, nullptr, nullptr, nullptr, &crs);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int i = crs.rows[r]; i < crs.rows[r + 1]; ++i) J(r, crs.cols[i]) = crs.values[i];
  ASSERT_EQ(J.cols(), 6 * n);  // tangent-space columns
  Eigen::VectorXd e(6 * n);
  for (int k = 0; k < n; ++k) e.segment<6>(6 * k) = estimate.pose(X(k)).minus(truth[k]);
  const double nees = e.dot(J.transpose() * (J * e));
  std::printf("NEES %.1f over %d dof\n", nees, 6 * n);
  // chi2(360) 0.1% and 99.9% quantiles are about 281 and 451.
  EXPECT_GT(nees, 281.0);
  EXPECT_LT(nees, 451.0);
  for (int k = 0; k < n; ++k)
    EXPECT_LT(estimate.pose(X(k)).q.angularDistance(truth[k].q), 0.05) << "pose " << k;
}

TEST(PoseGraph, NoiseFreeMeasurementsAreRecoveredExactly) {
  const int n = 40;
  const auto truth = helix(n);
  std::mt19937 rng(5);
  FactorGraph graph;
  Values initial;
  const auto noise = NoiseModel::isotropic(6, 0.01);
  graph.add(std::make_shared<testing::PosePriorFactor>(X(0), truth[0], noise));
  for (int k = 0; k < n; ++k) {
    initial.insertPose(X(k), k == 0 ? truth[0] : noisy(truth[k], rng, 0.3, 0.2));
    if (k > 0)
      graph.add(std::make_shared<testing::BetweenPoseFactor>(
          X(k - 1), X(k), truth[k - 1].inverse() * truth[k], noise));
    if (k >= 20)
      graph.add(std::make_shared<testing::BetweenPoseFactor>(
          X(k - 20), X(k), truth[k - 20].inverse() * truth[k], noise));
  }
  Values estimate = initial;
  OptimizerOptions options;
  options.max_iterations = 100;
  ASSERT_TRUE(optimize(graph, &estimate, options).usable);
  for (int k = 0; k < n; ++k) {
    EXPECT_LT((estimate.pose(X(k)).p - truth[k].p).norm(), 1e-6) << k;
    EXPECT_LT(estimate.pose(X(k)).q.angularDistance(truth[k].q), 1e-6) << k;
  }
}

}  // namespace
}  // namespace hdvio
