// hdvio's own Schur-complement Levenberg-Marquardt (schur_lm.h) against Ceres' DENSE_SCHUR on
// a small bundle-adjustment problem: poses, landmarks seen from every pose, a pose prior, a
// robust loss on some observations, and constant variables. Run to convergence, both must find
// the same minimum; the tangent Jacobians FactorT gives the solver must equal the ambient path.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

#include "between_pose_factor.h"
#include "point_in_body_factor.h"
#include "hdvio/core/ceres_bridge.h"
#include "hdvio/core/schur_lm.h"

namespace hdvio {
namespace {
using symbols::L;
using symbols::X;
using testing::PointInBodyFactor;

struct Problem {
  FactorGraph graph;
  Values initial;
  std::vector<Key> keys;
};

// 6 poses, 40 landmarks; every 7th observation is an outlier (1 m off) under a Cauchy loss.
Problem makeProblem(bool robust) {
  Problem pb;
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  const int poses = 6, landmarks = 40;
  std::vector<Pose> truth;
  for (int k = 0; k < poses; ++k)
    truth.emplace_back(quatExp(Vec3(0.03 * k, -0.02 * k, 0.1 * k)), Vec3(0.4 * k, 0.1 * k, 0.05 * k));
  std::vector<Vec3> points;
  for (int j = 0; j < landmarks; ++j) points.emplace_back(3.0 * n(rng), 3.0 * n(rng), 6.0 + n(rng));
  auto noise = NoiseModel::isotropic(3, 0.02);
  if (robust) noise = noise->robust(std::make_shared<ceres::CauchyLoss>(2.0));
  pb.graph.add(std::make_shared<testing::PosePriorFactor>(X(0), truth[0], NoiseModel::isotropic(6, 1e-3)));
  int count = 0;
  for (int k = 0; k < poses; ++k)
    for (int j = 0; j < landmarks; ++j) {
      Vec3 z = truth[k].R().transpose() * (points[j] - truth[k].p) + 0.02 * Vec3(n(rng), n(rng), n(rng));
      if (++count % 7 == 0) z += Vec3(1.0, -0.5, 0.3);
      pb.graph.add(std::make_shared<PointInBodyFactor>(X(k), L(j), z, noise));
    }
  for (int k = 0; k < poses; ++k) {
    Vec6 d;
    d << 0.1 * n(rng), 0.1 * n(rng), 0.1 * n(rng), 0.03 * n(rng), 0.03 * n(rng), 0.03 * n(rng);
    pb.initial.insertPose(X(k), truth[k].plus(d));
    pb.keys.push_back(X(k));
  }
  for (int j = 0; j < landmarks; ++j) {
    pb.initial.insertVector(L(j), points[j] + 0.2 * Vec3(n(rng), n(rng), n(rng)));
    pb.keys.push_back(L(j));
  }
  return pb;
}

OptimizerOptions converging(OptimizerOptions::Optimizer which) {
  OptimizerOptions o;
  o.optimizer = which;
  o.linear_solver = ceres::DENSE_SCHUR;
  o.eliminate_first = {'l'};
  o.max_iterations = 100;
  o.function_tolerance = 1e-14;
  return o;
}

double maxDifference(const Values& a, const Values& b, const std::vector<Key>& keys) {
  double d = 0.0;
  for (Key k : keys) d = std::max(d, a.minus(k, b).cwiseAbs().maxCoeff());
  return d;
}

TEST(SchurLm, FindsTheMinimumCeresFinds) {
  for (bool robust : {false, true}) {
    const Problem pb = makeProblem(robust);
    Values ceres_result = pb.initial, ours = pb.initial;
    const OptimizeResult rc = optimize(pb.graph, &ceres_result, converging(OptimizerOptions::Optimizer::kCeres));
    const OptimizeResult ro = optimize(pb.graph, &ours, converging(OptimizerOptions::Optimizer::kSchurLm));
    ASSERT_TRUE(rc.usable && ro.usable) << ro.summary.message;
    EXPECT_EQ(ro.summary.termination_type, ceres::CONVERGENCE) << ro.summary.message;
    EXPECT_NEAR(ro.summary.initial_cost, rc.summary.initial_cost, 1e-9 * rc.summary.initial_cost);
    EXPECT_NEAR(ro.summary.final_cost, rc.summary.final_cost, 1e-8 * rc.summary.final_cost) << "robust " << robust;
    EXPECT_LT(maxDifference(ours, ceres_result, pb.keys), 1e-6) << "robust " << robust;
    // The start was far from it: the comparison above is not trivially met.
    EXPECT_GT(maxDifference(pb.initial, ceres_result, pb.keys), 0.05);
    EXPECT_LT(ro.summary.final_cost, 0.5 * ro.summary.initial_cost);
  }
}

TEST(SchurLm, WithoutEliminationAndWithConstantKeysAgrees) {
  const Problem pb = makeProblem(true);
  OptimizerOptions with = converging(OptimizerOptions::Optimizer::kSchurLm);
  with.constant_keys = {X(1), L(3)};
  OptimizerOptions without = with;
  without.eliminate_first.clear();  // one dense system of all variables
  Values a = pb.initial, b = pb.initial, c = pb.initial;
  ASSERT_TRUE(optimize(pb.graph, &a, with).usable);
  ASSERT_TRUE(optimize(pb.graph, &b, without).usable);
  OptimizerOptions ceres_opts = with;
  ceres_opts.optimizer = OptimizerOptions::Optimizer::kCeres;
  ASSERT_TRUE(optimize(pb.graph, &c, ceres_opts).usable);
  EXPECT_LT(maxDifference(a, b, pb.keys), 1e-6);
  EXPECT_LT(maxDifference(a, c, pb.keys), 1e-6);
  for (Key k : {X(1), L(3)}) EXPECT_EQ(a.minus(k, pb.initial).norm(), 0.0) << k.str();
}

TEST(SchurLm, FewIterationsFromTheSameStartTakeTheSameFirstStep) {
  // One iteration from the same radius: the same damped Gauss-Newton step as Ceres (Ceres'
  // Jacobi scaling leaves the Levenberg-Marquardt step unchanged).
  const Problem pb = makeProblem(false);
  OptimizerOptions o = converging(OptimizerOptions::Optimizer::kSchurLm);
  o.max_iterations = 1;
  o.initial_trust_region_radius = 10.0;
  Values ours = pb.initial, ceres_result = pb.initial;
  ASSERT_TRUE(optimize(pb.graph, &ours, o).usable);
  o.optimizer = OptimizerOptions::Optimizer::kCeres;
  ASSERT_TRUE(optimize(pb.graph, &ceres_result, o).usable);
  EXPECT_LT(maxDifference(ours, ceres_result, pb.keys), 1e-8);
  EXPECT_GT(maxDifference(ours, pb.initial, pb.keys), 1e-3);
}

TEST(SchurLm, TangentJacobiansEqualTheAmbientPath) {
  const Problem pb = makeProblem(false);
  const Factor& f = *pb.graph[1];  // a PointInBodyFactor
  const double* x[2] = {pb.initial.data(f.keys()[0]), pb.initial.data(f.keys()[1])};
  const ceres::Manifold* m[2] = {pb.initial.manifold(f.keys()[0]), nullptr};
  double r_direct[3], r_base[3], J0[18], J1[9], B0[18], B1[9];
  double* direct[2] = {J0, J1};
  double* base[2] = {B0, B1};
  ASSERT_TRUE(f.evaluateTangent(x, m, r_direct, direct));
  ASSERT_TRUE(f.Factor::evaluateTangent(x, m, r_base, base));  // through costFunction()
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(r_direct[i], r_base[i], 1e-12);
  for (int i = 0; i < 18; ++i) EXPECT_NEAR(J0[i], B0[i], 1e-9);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(J1[i], B1[i], 1e-12);
}

// r = x - 10 on a 3-vector whose evaluation fails beyond |x_i| = 3 (a landmark that would move
// behind the camera): steps that land there are unsuccessful, the radius shrinks and the solve
// goes on, as in Ceres, instead of ending as FAILURE after a few of them.
class FailsBeyondFactor : public FactorT<FailsBeyondFactor, 3, Vec3Var> {
 public:
  FailsBeyondFactor(Key k, NoiseModelPtr noise) : FactorT({k}, std::move(noise)) {}
  bool evaluateError(const double* const* x, double* residual, double** J) const {
    const Eigen::Map<const Vec3> v(x[0]);
    if (v.cwiseAbs().maxCoeff() > 3.0) return false;
    Eigen::Map<Vec3> r(residual);
    r = v - Vec3::Constant(10.0);
    if (J && J[0]) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Jx(J[0]);
      Jx.setIdentity();
    }
    return true;
  }
};

TEST(SchurLm, AStepThatCannotBeEvaluatedIsRejectedNotFatal) {
  FactorGraph graph;
  graph.add(std::make_shared<FailsBeyondFactor>(L(0), NoiseModel::isotropic(3, 1.0)));
  Values start;
  start.insertVector(L(0), Vec3::Zero());
  OptimizerOptions o = converging(OptimizerOptions::Optimizer::kSchurLm);
  o.eliminate_first.clear();
  o.max_iterations = 30;
  o.initial_trust_region_radius = 1e8;  // the first steps jump to 10, beyond the boundary
  Values ours = start, ceres_result = start;
  const OptimizeResult ro = optimize(graph, &ours, o);
  o.optimizer = OptimizerOptions::Optimizer::kCeres;
  const OptimizeResult rc = optimize(graph, &ceres_result, o);
  ASSERT_TRUE(rc.usable) << rc.summary.FullReport();
  ASSERT_TRUE(ro.usable) << ro.summary.message;
  EXPECT_GT(ours.vec3(L(0)).minCoeff(), 2.0);  // it moved towards the minimum, up to the edge
  EXPECT_NEAR(ro.summary.final_cost, rc.summary.final_cost, 1e-6 * rc.summary.final_cost);
  // The same rejected steps; the own solver may stop one step sooner (next test).
  EXPECT_LE(ro.summary.iterations.size(), rc.summary.iterations.size());
  EXPECT_GE(ro.summary.iterations.size() + 1, rc.summary.iterations.size());
}

// r = x - c: the cost is quadratic, so the first nearly undamped step lowers it by exactly what
// the model predicted and lands on the minimum. The own solver stops there; Ceres computes one
// more step only to find that it lowers the cost by nothing.
class OffsetFactor : public FactorT<OffsetFactor, 3, Vec3Var> {
 public:
  OffsetFactor(Key k, Vec3 c, NoiseModelPtr noise) : FactorT({k}, std::move(noise)), c_(std::move(c)) {}
  bool evaluateError(const double* const* x, double* residual, double** J) const {
    Eigen::Map<Vec3> r(residual);
    r = Eigen::Map<const Vec3>(x[0]) - c_;
    if (J && J[0]) Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(J[0]).setIdentity();
    return true;
  }

 private:
  Vec3 c_;
};

TEST(SchurLm, StopsWhenTheStepLoweredTheCostAsTheModelPredicted) {
  // Two offsets: the minimum (0, 0, 2) keeps a cost of 600, as a window's does.
  FactorGraph quadratic;
  quadratic.add(std::make_shared<OffsetFactor>(L(0), Vec3(1.0, -2.0, 3.0), NoiseModel::isotropic(3, 0.1)));
  quadratic.add(std::make_shared<OffsetFactor>(L(0), Vec3(-1.0, 2.0, 1.0), NoiseModel::isotropic(3, 0.1)));
  Values start;
  start.insertVector(L(0), Vec3::Zero());
  OptimizerOptions o = converging(OptimizerOptions::Optimizer::kSchurLm);
  o.eliminate_first.clear();
  o.function_tolerance = 1e-6;
  o.initial_trust_region_radius = 1e8;
  Values ours = start, ceres_result = start;
  const OptimizeResult ro = optimize(quadratic, &ours, o);
  o.optimizer = OptimizerOptions::Optimizer::kCeres;
  const OptimizeResult rc = optimize(quadratic, &ceres_result, o);
  ASSERT_TRUE(ro.usable && rc.usable);
  EXPECT_EQ(ro.summary.termination_type, ceres::CONVERGENCE);
  EXPECT_EQ(ro.summary.iterations.size(), 2u);  // iteration 0 and the one step
  EXPECT_EQ(rc.summary.iterations.size(), 2u);  // Ceres' third, the probe, is not recorded ...
  EXPECT_LT((ours.vec3(L(0)) - ceres_result.vec3(L(0))).norm(), 1e-7);
  EXPECT_LT((ours.vec3(L(0)) - Vec3(0.0, 0.0, 2.0)).norm(), 1e-7);
  // ... but its step count is: one linear solve against two.
  EXPECT_EQ(rc.summary.num_linear_solves, 2);
  EXPECT_EQ(ro.summary.num_linear_solves, 1);

  // On the bundle-adjustment problem it ends where Ceres ends (to the tolerance) with fewer
  // linear solves.
  const Problem pb = makeProblem(false);
  OptimizerOptions ba = converging(OptimizerOptions::Optimizer::kSchurLm);
  ba.function_tolerance = 1e-4;
  ba.initial_trust_region_radius = 1e8;
  Values ours_ba = pb.initial, ceres_ba = pb.initial;
  const OptimizeResult rob = optimize(pb.graph, &ours_ba, ba);
  ba.optimizer = OptimizerOptions::Optimizer::kCeres;
  const OptimizeResult rcb = optimize(pb.graph, &ceres_ba, ba);
  ASSERT_TRUE(rob.usable && rcb.usable);
  EXPECT_NEAR(rob.summary.final_cost, rcb.summary.final_cost, 1e-5 * rcb.summary.final_cost);
  EXPECT_LT(rob.summary.num_linear_solves, rcb.summary.num_linear_solves);
}

TEST(SchurLm, AFactorOnTwoEliminatedVariablesIsAnError) {
  Problem pb = makeProblem(false);
  pb.graph.add(std::make_shared<testing::BetweenPoseFactor>(X(0), X(1), Pose(), NoiseModel::isotropic(6, 1.0)));
  OptimizerOptions o = converging(OptimizerOptions::Optimizer::kSchurLm);
  o.eliminate_first = {'x'};
  Values v = pb.initial;
  EXPECT_THROW(optimize(pb.graph, &v, o), std::logic_error);
}

}  // namespace
}  // namespace hdvio
