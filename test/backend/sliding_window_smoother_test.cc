// The fixed-lag smoother with Schur marginalization reproduces the batch solution on the
// variables still in its window.
#include "hdvio/backend/sliding_window_smoother.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "between_pose_factor.h"

namespace hdvio {
namespace {
using symbols::X;

// Noisy absolute position (e.g. GNSS) on one pose.
class PositionFactor : public FactorT<PositionFactor, 3, PoseVar> {
 public:
  PositionFactor(Key k, const Vec3& z, NoiseModelPtr noise) : FactorT({k}, std::move(noise)), z_(z) {}
  bool evaluateError(const double* const* x, double* r, double** J) const {
    Eigen::Map<Vec3> res(r);
    res = Eigen::Map<const Vec3>(x[0]) - z_;
    if (J && J[0]) {
      Eigen::Map<Eigen::Matrix<double, 3, 6, Eigen::RowMajor>> J0(J[0]);
      J0.setZero();
      J0.leftCols<3>().setIdentity();
    }
    return true;
  }

 private:
  Vec3 z_;
};

struct Problem {
  std::vector<Pose> truth;
  std::vector<FactorGraph> factors_at;  // factors that arrive with pose k
  std::vector<Pose> initial;
};

Problem makeProblem(int n, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Problem p;
  const double sp = 0.02, sr = 0.005, sgps = 0.3;
  Eigen::VectorXd sig(6);
  sig << sp, sp, sp, sr, sr, sr;
  Pose chained;
  for (int k = 0; k < n; ++k) {
    const double a = 0.15 * k;
    p.truth.emplace_back(quatExp(Vec3(0.1 * std::sin(a), 0.05 * std::cos(a), a)),
                         Vec3(4.0 * std::cos(a), 4.0 * std::sin(a), 0.3 * std::sin(2 * a)));
    FactorGraph f;
    if (k == 0) {
      f.add(std::make_shared<testing::PosePriorFactor>(X(0), p.truth[0], NoiseModel::isotropic(6, 0.01)));
      chained = p.truth[0];
    } else {
      Vec6 d;
      for (int i = 0; i < 6; ++i) d[i] = sig[i] * g(rng);
      const Pose z = (p.truth[k - 1].inverse() * p.truth[k]).plus(d);
      f.add(std::make_shared<testing::BetweenPoseFactor>(X(k - 1), X(k), z, NoiseModel::diagonal(sig)));
      chained = chained * z;
    }
    const Vec3 gps = p.truth[k].p + sgps * Vec3(g(rng), g(rng), g(rng));
    f.add(std::make_shared<PositionFactor>(X(k), gps, NoiseModel::isotropic(3, sgps)));
    p.factors_at.push_back(f);
    p.initial.push_back(chained);
  }
  return p;
}

TEST(SlidingWindowSmoother, MatchesBatchOnTheWindow) {
  std::mt19937 rng(21);
  const int n = 40, window = 8;
  const Problem p = makeProblem(n, rng);

  FactorGraph all;
  Values batch;
  for (int k = 0; k < n; ++k) {
    all.add(p.factors_at[k]);
    batch.insertPose(X(k), p.initial[k]);
  }
  OptimizerOptions opt;
  opt.max_iterations = 100;
  ASSERT_TRUE(optimize(all, &batch, opt).usable);

  SmootherOptions so;
  so.optimizer.max_iterations = 20;
  SlidingWindowSmoother smoother(so);
  for (int k = 0; k < n; ++k) {
    Values v;
    // Initialize the newest pose by odometry from the current estimate.
    v.insertPose(X(k), k == 0 ? p.initial[0]
                              : smoother.estimate().pose(X(k - 1)) *
                                    (p.initial[k - 1].inverse() * p.initial[k]));
    ASSERT_TRUE(smoother.update(p.factors_at[k], v).usable);
    if (k >= window) smoother.marginalize({X(k - window)});
  }
  ASSERT_EQ(smoother.estimate().size(), static_cast<std::size_t>(window));
  double worst_p = 0.0, batch_err = 0.0;
  for (int k = n - window; k < n; ++k) {
    const Pose a = smoother.estimate().pose(X(k)), b = batch.pose(X(k));
    worst_p = std::max(worst_p, (a.p - b.p).norm());
    EXPECT_LT(a.q.angularDistance(b.q), 2e-3) << k;
    batch_err = std::max(batch_err, (b.p - p.truth[k].p).norm());
  }
  std::printf("smoother vs batch: %.5f m (batch vs truth: %.4f m)\n", worst_p, batch_err);
  EXPECT_LT(worst_p, 0.01);
  EXPECT_LT(worst_p, 0.2 * batch_err);
}

TEST(SlidingWindowSmoother, LagRuleAndBookkeeping) {
  std::mt19937 rng(22);
  const Problem p = makeProblem(12, rng);
  SmootherOptions so;
  so.lag_s = 0.45;  // keys older than newest - 0.45 s leave
  SlidingWindowSmoother smoother(so);
  for (int k = 0; k < 12; ++k) {
    Values v;
    v.insertPose(X(k), p.initial[k]);
    const auto r = smoother.update(p.factors_at[k], v, {{X(k), fromSeconds(0.1 * k)}});
    ASSERT_TRUE(r.usable);
    ASSERT_EQ(r.new_factor_ids.size(), p.factors_at[k].size());
  }
  // Timestamps 0.7 ... 1.1 s remain (0.65 s cutoff).
  EXPECT_EQ(smoother.estimate().size(), 5u);
  EXPECT_FALSE(smoother.estimate().exists(X(6)));
  EXPECT_TRUE(smoother.estimate().exists(X(7)));
  smoother.removeVariables({X(11)});
  EXPECT_FALSE(smoother.estimate().exists(X(11)));
  for (const auto& f : smoother.factors())
    for (Key k : f->keys()) EXPECT_TRUE(smoother.estimate().exists(k));
  EXPECT_THROW(smoother.update({}, [&] { Values v; v.insertPose(X(7), Pose()); return v; }()),
               std::logic_error);
}

// With the warm start, well-posed solves grow the Levenberg-Marquardt radius from the initial
// value up to the cap, and it stays within [min, max]; without it nothing is carried.
TEST(SlidingWindowSmoother, WarmStartCarriesTheTrustRegionWithinItsBounds) {
  std::mt19937 rng(23);
  const Problem p = makeProblem(15, rng);
  for (const bool warm : {true, false}) {
    SmootherOptions so;
    so.optimizer.max_iterations = 20;
    so.optimizer.initial_trust_region_radius = 1e2;
    if (warm) {
      so.warm_start_min_radius = 1e2;
      so.warm_start_max_radius = 1e6;
    }
    SlidingWindowSmoother smoother(so);
    double largest = 0.0;
    for (int k = 0; k < 15; ++k) {
      Values v;
      v.insertPose(X(k), p.initial[k]);
      ASSERT_TRUE(smoother.update(p.factors_at[k], v).usable);
      const double r = smoother.trustRegionRadius();
      if (warm) {
        EXPECT_GE(r, 1e2) << k;
        EXPECT_LE(r, 1e6) << k;
      } else {
        EXPECT_EQ(r, 0.0) << k;
      }
      largest = std::max(largest, r);
    }
    // Each solve starts where the last ended, so the growth accumulates up to the cap (a solve
    // from 1e2 alone ends near 1e3-1e4).
    if (warm) {
      EXPECT_EQ(largest, 1e6);
    }
  }
}

}  // namespace
}  // namespace hdvio
