// Marginalization that eliminates the leaving landmarks one by one (each a 3x3 Schur
// complement onto its observing poses) must equal one dense Schur complement of everything.
#include <gtest/gtest.h>

#include <random>

#include "between_pose_factor.h"
#include "hdvio/backend/schur_marginalization.h"
#include "hdvio/core/numerical_jacobian.h"

namespace hdvio {
namespace {
using symbols::L;
using symbols::X;

// Pinhole-like bearing observation of a landmark (unit focal length): 2 residuals, rank 2 in
// the landmark, so a landmark seen once has a rank-deficient block (depth unobservable).
class BearingFactor : public FactorT<BearingFactor, 2, PoseVar, VectorVar<3>> {
 public:
  BearingFactor(Key pose, Key landmark, const Eigen::Vector2d& z, NoiseModelPtr noise)
      : FactorT({pose, landmark}, std::move(noise)), z_(z) {}
  bool evaluateError(const double* const* x, double* residual, double** J) const {
    const Eigen::Map<const Vec3> p(x[0]), l(x[1]);
    const Eigen::Map<const Quat> q(x[0] + 3);
    const Mat3 Rt = q.toRotationMatrix().transpose();
    const Vec3 c = Rt * (l - p);
    Eigen::Map<Eigen::Vector2d> r(residual);
    r = c.head<2>() / c.z() - z_;
    if (!J) return true;
    Eigen::Matrix<double, 2, 3> proj;
    proj << 1.0 / c.z(), 0.0, -c.x() / (c.z() * c.z()), 0.0, 1.0 / c.z(), -c.y() / (c.z() * c.z());
    if (J[0]) {
      Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> Jp(J[0]);
      Jp.leftCols<3>() = -proj * Rt;
      Jp.rightCols<3>() = proj * hat(c);  // R Exp(d): c = Exp(-d) R^T (l - p)
    }
    if (J[1]) {
      Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jl(J[1]);
      Jl = proj * Rt;
    }
    return true;
  }

 private:
  Eigen::Vector2d z_;
};

struct Scene {
  FactorGraph graph;
  Values values;
  int poses = 6;
  int landmarks = 40;
};

// Poses looking along +z at a landmark cloud; every landmark seen by min_seen-5 poses, one of them x0
// for the first half; noisy measurements and perturbed values (linearization away from truth).
Scene makeScene(std::mt19937& rng, int min_seen = 1) {
  Scene s;
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_int_distribution<int> seen(min_seen, 5);
  std::vector<Pose> truth;
  for (int k = 0; k < s.poses; ++k) {
    truth.emplace_back(quatExp(Vec3(0.05 * g(rng), 0.05 * g(rng), 0.1 * g(rng))),
                       Vec3(0.3 * k, 0.1 * g(rng), 0.1 * g(rng)));
    s.values.insertPose(X(k), truth[k].plus(0.01 * Vec6(Vec6::Random())));
  }
  const auto pixel = NoiseModel::isotropic(2, 0.01);
  const auto odometry = NoiseModel::isotropic(6, 0.05);
  for (int k = 0; k + 1 < s.poses; ++k)
    s.graph.add(std::make_shared<testing::BetweenPoseFactor>(
        X(k), X(k + 1), truth[k].inverse() * truth[k + 1], odometry));
  for (int j = 0; j < s.landmarks; ++j) {
    const Vec3 lm(2.0 * g(rng), 2.0 * g(rng), 6.0 + g(rng));
    s.values.insertVector(L(j), lm + 0.05 * Vec3(g(rng), g(rng), g(rng)));
    const int first = j < s.landmarks / 2 ? 0 : 1;
    const int count = std::min(seen(rng), s.poses - first);
    for (int k = first; k < first + count; ++k) {
      const Vec3 c = truth[k].inverse() * lm;
      const Eigen::Vector2d z = c.head<2>() / c.z() + 0.01 * Eigen::Vector2d(g(rng), g(rng));
      s.graph.add(std::make_shared<BearingFactor>(X(k), L(j), z, pixel));
    }
  }
  return s;
}

struct PriorSystem {
  Eigen::MatrixXd H;
  Eigen::VectorXd b;
  long rank = 0;
};

PriorSystem priorOf(const Scene& s, const std::set<Key>& removed, bool landmarks_first) {
  MarginalizationOptions o;
  o.eliminate_independent_first = landmarks_first;
  const auto prior = marginalizeBySchurComplement(s.graph, s.values, removed, o);
  EXPECT_TRUE(prior);
  if (!prior) return {};
  const Eigen::MatrixXd& J = prior->jacobian();
  return {J.transpose() * J, J.transpose() * prior->residualAtLinearizationPoint(), J.rows()};
}

TEST(LandmarkElimination, BearingFactorJacobiansMatchNumeric) {
  std::mt19937 rng(11);
  const Scene s = makeScene(rng);
  for (const auto& f : s.graph) EXPECT_LT(maxJacobianError(*f, s.values), 1e-6);
}

TEST(LandmarkElimination, EqualsDenseSchurComplement) {
  std::mt19937 rng(12);
  const Scene s = makeScene(rng);
  // The oldest pose and the landmarks it saw first leave (as a keyframe leaving the window).
  std::set<Key> removed{X(0)};
  for (int j = 0; j < s.landmarks / 2; ++j) removed.insert(L(j));
  const PriorSystem sparse = priorOf(s, removed, true);
  const PriorSystem dense = priorOf(s, removed, false);
  ASSERT_EQ(sparse.H.rows(), dense.H.rows());
  EXPECT_EQ(sparse.rank, dense.rank);
  EXPECT_LT((sparse.H - dense.H).norm(), 1e-8 * dense.H.norm());
  EXPECT_LT((sparse.b - dense.b).norm(), 1e-8 * std::max(1.0, dense.b.norm()));
}

TEST(LandmarkElimination, EqualsInverseOfFullSystemWhenAnchored) {
  // With a prior anchoring every pose the full system is invertible: the prior's covariance must
  // be the marginal covariance of the remaining variables, whatever the elimination order.
  std::mt19937 rng(13);
  Scene s = makeScene(rng, /*min_seen=*/2);
  for (int k = 0; k < s.poses; ++k)
    s.graph.add(std::make_shared<testing::PosePriorFactor>(X(k), s.values.pose(X(k)),
                                                           NoiseModel::isotropic(6, 1.0)));
  std::set<Key> removed{X(0), X(1)};
  for (int j = 0; j < s.landmarks; j += 2) removed.insert(L(j));
  std::vector<Key> order(removed.begin(), removed.end());
  std::vector<Key> rest;
  for (Key k : s.graph.keys())
    if (!removed.count(k)) rest.push_back(k);
  order.insert(order.end(), rest.begin(), rest.end());
  const LinearSystem full = linearizeDense(s.graph, s.values, order);
  const Eigen::MatrixXd cov = full.H.inverse();
  const PriorSystem sparse = priorOf(s, removed, true);
  const int r = static_cast<int>(sparse.H.rows());
  const Eigen::MatrixXd cov_prior = sparse.H.inverse();
  EXPECT_LT((cov_prior - cov.bottomRightCorner(r, r)).norm(), 1e-6 * cov.bottomRightCorner(r, r).norm());
}

}  // namespace
}  // namespace hdvio
