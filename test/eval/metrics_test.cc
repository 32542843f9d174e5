// Statistics, association, evo RPE pair selection and the rpg relative error on trajectories
// whose errors are known in closed form.
#include <gtest/gtest.h>

#include <cmath>

#include "hdvio/core/error.h"
#include "hdvio/eval/association.h"
#include "hdvio/eval/evaluation.h"
#include "hdvio/eval/pose_errors.h"
#include "hdvio/eval/signal_errors.h"
#include "hdvio/eval/statistics.h"

namespace hdvio::eval {
namespace {

// Straight line along x, `step` metres apart, 10 Hz.
Trajectory line(int n, double step, double x_scale = 1.0) {
  Trajectory t;
  for (int i = 0; i < n; ++i)
    t.push(i * kNanosPerSecond / 10, Vec3(x_scale * step * i, 0, 1), Mat3::Identity());
  return t;
}

TEST(EvalStatistics, MatchesNumpyDefinitions) {
  const ErrorStatistics s = computeStatistics({1.0, 2.0, 3.0, 4.0});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4.0));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));  // population std, numpy's default
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_DOUBLE_EQ(computeStatistics({5.0, 1.0, 3.0}).median, 3.0);
  EXPECT_TRUE(std::isnan(computeStatistics({}).rmse));
}

TEST(EvalAssociation, NearestStampWithinToleranceLikeEvo) {
  Trajectory ref = line(10, 1.0);  // stamps 0, 0.1, ..., 0.9 s
  Trajectory est;
  // 0.104 s matches 0.1 s (4 ms away); 0.355 s is 45 ms from 0.4 s: no match at the default
  // 10 ms tolerance; 0.6 s matches exactly.
  for (Timestamp t : {104'000'000LL, 355'000'000LL, 600'000'000LL})
    est.push(t, Vec3::Zero(), Mat3::Identity());
  AssociationOptions o;
  const AssociatedPair p = associate(ref, est, o);
  ASSERT_EQ(p.est.size(), 2u);
  EXPECT_EQ(p.ref.t[0], 100'000'000LL);
  EXPECT_EQ(p.ref.t[1], 600'000'000LL);
  EXPECT_EQ(p.est.t[0], 104'000'000LL);
}

// A repeated stamp in the longer trajectory: np.argmin takes the first of the equal stamps,
// whether the query lies before, on or after them; repeats in the shorter one are each matched.
TEST(EvalAssociation, RepeatedStampsAreMatchedLikeEvo) {
  Trajectory ref;
  ref.push(0, Vec3(0, 0, 0), Mat3::Identity());
  ref.push(100'000'000LL, Vec3(1, 0, 0), Mat3::Identity());
  ref.push(100'000'000LL, Vec3(2, 0, 0), Mat3::Identity());
  ref.push(100'000'000LL, Vec3(3, 0, 0), Mat3::Identity());
  ref.push(300'000'000LL, Vec3(4, 0, 0), Mat3::Identity());
  Trajectory est;
  for (Timestamp t : {97'000'000LL, 100'000'000LL, 103'000'000LL})
    est.push(t, Vec3::Zero(), Mat3::Identity());
  const AssociatedPair p = associate(ref, est, AssociationOptions{});
  ASSERT_EQ(p.ref.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(p.ref.p[i].x(), 1.0) << i;
  // Each query takes the first pose of the repeat, also when the estimate is the longer one.
  const AssociatedPair q = associate(est, ref, AssociationOptions{});
  ASSERT_EQ(q.est.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(q.est.p[i].x(), 1.0) << i;
  // A repeat in the shorter trajectory: both poses stay, matched to the same pose.
  Trajectory twice;
  twice.push(100'000'000LL, Vec3(7, 0, 0), Mat3::Identity());
  twice.push(100'000'000LL, Vec3(8, 0, 0), Mat3::Identity());
  const AssociatedPair r = associate(line(10, 1.0), twice, AssociationOptions{});
  ASSERT_EQ(r.est.size(), 2u);
  EXPECT_EQ(r.est.p[1].x(), 8.0);
  EXPECT_EQ(r.ref.t[0], r.ref.t[1]);
}

TEST(EvalAssociation, TimeOffsetShiftsTheEstimate) {
  Trajectory ref = line(10, 1.0);
  Trajectory est = line(10, 1.0);
  for (Timestamp& t : est.t) t -= 500'000'000LL;  // estimate clock 0.5 s behind
  AssociationOptions o;
  o.time_offset_s = 0.5;
  EXPECT_EQ(associate(ref, est, o).est.size(), 10u);
  o.time_offset_s = 0.0;
  EXPECT_EQ(associate(ref, est, o).est.size(), 5u);
}

TEST(EvalAssociation, InterpolationIsExactOnLinearMotion) {
  Trajectory ref = line(10, 1.0);
  ref.R.assign(ref.size(), Mat3::Identity());
  for (std::size_t i = 0; i < ref.size(); ++i)
    ref.R[i] = Eigen::AngleAxisd(0.1 * i, Vec3::UnitZ()).toRotationMatrix();
  Trajectory est;
  est.push(125'000'000LL, Vec3::Zero(), Mat3::Identity());  // a quarter between 0.1 and 0.2 s
  AssociationOptions o;
  o.mode = AssociationMode::kInterpolate;
  o.max_time_diff_s = 0.05;
  const AssociatedPair p = associate(ref, est, o);
  ASSERT_EQ(p.ref.size(), 1u);
  EXPECT_NEAR(p.ref.p[0].x(), 1.25, 1e-12);
  const Mat3 expected = Eigen::AngleAxisd(0.125, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_LT((p.ref.R[0] - expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(EvalAssociation, IndexNeedsEqualLengthsAndNoMatchIsAnError) {
  AssociationOptions o;
  o.mode = AssociationMode::kIndex;
  EXPECT_THROW(associate(line(5, 1.0), line(6, 1.0), o), InputError);
  Trajectory far = line(5, 1.0);
  for (Timestamp& t : far.t) t += 100 * kNanosPerSecond;
  EXPECT_THROW(associate(line(5, 1.0), far, AssociationOptions{}), InputError);
}

TEST(EvalEvoPairs, PathDeltaStartsAfterTheFirstDeltaLikeEvo) {
  // evo's filter_pairs_by_path: ids where the accumulated path reaches delta: 3, 6, 9.
  EvoRpeOptions o{3.0, DeltaUnit::kMeters, false, 0.1, false};
  const IndexPairs pairs = evoPairs(line(11, 1.0).p, o);
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].first, 3u);
  EXPECT_EQ(pairs[0].second, 6u);
  EXPECT_EQ(pairs[1].first, 6u);
  EXPECT_EQ(pairs[1].second, 9u);
}

TEST(EvalEvoPairs, FramesAndAllPairs) {
  const std::vector<Vec3> p = line(10, 1.0).p;
  EXPECT_EQ(evoPairs(p, {3.0, DeltaUnit::kFrames, false, 0.1, false}).size(), 3u);  // 0-3-6-9
  EXPECT_EQ(evoPairs(p, {3.0, DeltaUnit::kFrames, true, 0.1, false}).size(), 7u);
  const IndexPairs all = evoPairs(p, {2.0, DeltaUnit::kMeters, true, 0.1, false});
  ASSERT_EQ(all.size(), 8u);
  for (const auto& [i, j] : all) EXPECT_EQ(j, i + 2);
  EXPECT_TRUE(evoPairs(p, {100.0, DeltaUnit::kMeters, false, 0.1, false}).empty());
}

TEST(EvalEvoRelativeError, ScaleErrorGivesKnownTranslationError) {
  // Estimate moves 1.1 m per true metre: over a 2-frame pair (2 m true) the error is 0.2 m.
  const Trajectory ref = line(20, 1.0), est = line(20, 1.0, 1.1);
  const RelativeErrors r = evoRelativeErrors(ref, est, {2.0, DeltaUnit::kFrames, false, 0.1, false});
  for (double e : r.translation) EXPECT_NEAR(e, 0.2, 1e-12);
  for (double e : r.rotation_deg) EXPECT_NEAR(e, 0.0, 1e-6);
}

TEST(EvalRpgRelativeError, ScaleErrorGivesKnownPercentAndSampleCount) {
  const Trajectory ref = line(101, 0.1), est = line(101, 0.1, 1.1);  // 10 m
  const RpgRelativeError r = rpgRelativeError(ref, est, 2.0, 0.35);
  // Starts 0..80 reach exactly 2 m further; 81..83 end at the last pose, within 0.35 m of it.
  EXPECT_EQ(r.translation.size(), 84u);
  EXPECT_NEAR(r.translation[0], 0.2, 1e-9);
  EXPECT_NEAR(r.translation_percent[0], 10.0, 1e-7);
  EXPECT_NEAR(r.rotation_deg[0], 0.0, 1e-6);
  // The Sim(3) scale correction removes it.
  const RpgRelativeError corrected = rpgRelativeError(ref, est, 2.0, 0.35, 1.0 / 1.1);
  EXPECT_NEAR(corrected.translation[0], 0.0, 1e-9);
}

TEST(EvalRpgRelativeError, YawDriftShowsAsYawNotGravity) {
  Trajectory ref = line(101, 0.1), est = line(101, 0.1);
  for (std::size_t i = 0; i < est.size(); ++i)
    est.R[i] = Eigen::AngleAxisd(0.001 * i, Vec3::UnitZ()).toRotationMatrix();  // 0.01 rad per m
  const RpgRelativeError r = rpgRelativeError(ref, est, 5.0);
  ASSERT_FALSE(r.yaw_deg.empty());
  EXPECT_NEAR(r.yaw_deg[0], 0.05 * 180.0 / M_PI, 1e-9);
  EXPECT_NEAR(r.rotation_deg[0], 0.05 * 180.0 / M_PI, 1e-6);
  EXPECT_NEAR(r.gravity_deg[0], 0.0, 1e-9);
}

TEST(EvalRpgDistances, TruncatedFractionsOfTheLength) {
  const std::vector<double> d = rpgDistancesFromFractions(123.456, {0.1, 0.5});
  EXPECT_DOUBLE_EQ(d[0], 12.34);
  EXPECT_DOUBLE_EQ(d[1], 61.72);
}

TEST(EvalAbsoluteErrors, TranslationAndRotation) {
  Trajectory ref = line(3, 1.0), est = line(3, 1.0);
  est.p[1] += Vec3(0, 0.3, 0.4);
  est.R[2] = Eigen::AngleAxisd(0.1, Vec3::UnitX()).toRotationMatrix();
  const AbsoluteErrors e = absoluteErrors(ref, est);
  EXPECT_NEAR(e.translation[1], 0.5, 1e-12);
  EXPECT_NEAR(e.rotation_deg[2], 0.1 * 180.0 / M_PI, 1e-6);
}

TEST(EvalForceErrors, ExternalAndTotalSplitIntoXyAndZ) {
  ForceGroundTruth gt;
  VectorSeries est;
  for (int i = 0; i < 4; ++i) {
    gt.t.push_back(i * 10'000'000LL);
    gt.external.emplace_back(1, 0, 0);
    gt.drag.emplace_back(0, 0, -1);
    est.t.push_back(i * 10'000'000LL + 1000);
    est.value.emplace_back(1, 0, -1);  // equals the total force, misses the external by (0,0,-1)
  }
  const auto f = forceErrors(gt, est, 5'000'000LL);
  ASSERT_TRUE(f.has_value());
  EXPECT_NEAR(f->total.total.rmse, 0.0, 1e-12);
  EXPECT_NEAR(f->external.total.rmse, 1.0, 1e-12);
  EXPECT_NEAR(f->external.z.rmse, 1.0, 1e-12);
  EXPECT_NEAR(f->external.xy.rmse, 0.0, 1e-12);
}

// An estimate with a separate total non-thrust force (hdvio: residual + external) is scored
// on it for the "total" errors and on its external force for the "external" ones.
TEST(EvalForceErrors, TotalForceOfTheEstimateIsUsedForTheTotalColumn) {
  GroundTruth gt;
  gt.trajectory = line(4, 1.0);
  gt.forces = ForceGroundTruth{};
  Estimate est;
  est.trajectory = line(4, 1.0);
  est.force = VectorSeries{};
  est.total_force = VectorSeries{};
  for (int i = 0; i < 4; ++i) {
    const Timestamp t = i * kNanosPerSecond / 10;
    gt.forces->t.push_back(t);
    gt.forces->external.emplace_back(0.5, 0, 0);
    gt.forces->drag.emplace_back(-3, 0, 0);
    est.force->t.push_back(t);
    est.force->value.emplace_back(0.5, 0, 0);        // the external force, exact
    est.total_force->t.push_back(t);
    est.total_force->value.emplace_back(-2.5, 0, 0.2);  // drag + external, off by 0.2 in z
  }
  EvaluationOptions options;
  options.evo_rpe = false;
  options.rpe_fractions.clear();
  EstimateResult r = evaluateEstimate(gt, est, options, {});
  ASSERT_TRUE(r.force.has_value());
  EXPECT_NEAR(r.force->external.total.rmse, 0.0, 1e-12);
  EXPECT_NEAR(r.force->total.total.rmse, 0.2, 1e-12);
  EXPECT_NEAR(r.force->total.xy.rmse, 0.0, 1e-12);
  // Without it, the external force stands for the total (vimo / vid): off by the drag.
  est.total_force.reset();
  r = evaluateEstimate(gt, est, options, {});
  ASSERT_TRUE(r.force.has_value());
  EXPECT_NEAR(r.force->total.total.rmse, 3.0, 1e-12);
}

TEST(EvalVelocityErrors, EstimateIsRotatedByTheAlignment) {
  Trajectory gt = line(3, 1.0);
  gt.v.assign(3, Vec3(0, 1, 0));
  VectorSeries est{"", gt.t, {Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0)}};
  SimilarityTransform T;
  T.R = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
  const auto e = velocityErrors(gt, est, T, 1000);
  ASSERT_TRUE(e.has_value());
  EXPECT_NEAR(e->total.rmse, 0.0, 1e-12);
  EXPECT_NEAR(velocityErrors(gt, est, SimilarityTransform{}, 1000)->total.rmse, std::sqrt(2.0), 1e-12);
}

// posyaw fits the yaw to the positions: on a trajectory that is small against its position
// error the fitted yaw (and ATE_R) is noise, and the result says so; on a large one it does not.
TEST(EvalYawAlignmentNote, SmallTrajectoriesAgainstTheirErrorAreFlagged) {
  const auto evaluateWithError = [](double extent) {
    GroundTruth gt;
    Estimate est;
    for (int i = 0; i < 40; ++i) {
      const double a = 2.0 * M_PI * i / 40.0;
      const Timestamp t = i * kNanosPerSecond / 10;
      const Vec3 p(extent * std::cos(a), extent * std::sin(a), 1.0);
      gt.trajectory.push(t, p, Mat3::Identity());
      // A 0.3 m error that is not a rigid motion: alternating along x.
      est.trajectory.push(t, p + Vec3(i % 2 ? 0.3 : -0.3, 0, 0), Mat3::Identity());
    }
    EvaluationOptions options;
    options.alignment = AlignmentType::kPosYaw;
    options.evo_rpe = false;
    options.rpe_fractions.clear();
    return evaluateEstimate(gt, est, options, {});
  };
  const auto flagged = [](const EstimateResult& r) {
    for (const auto& n : r.notes)
      if (n.find("ill-determined") != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(flagged(evaluateWithError(0.5)));   // radius 0.5 m < 3 x 0.3 m
  EXPECT_FALSE(flagged(evaluateWithError(5.0)));  // radius 5 m
}

}  // namespace
}  // namespace hdvio::eval
