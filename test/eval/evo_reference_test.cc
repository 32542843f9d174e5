// Reproduces the values evo stores for its KITTI 00 test data (../shared/data/reference_metrics):
// APE translation part with SE(3) Umeyama alignment, RPE translation part with delta 10 m on
// consecutive pairs, index association. And evo_ape's value for its EuRoC V1_02 ORB-SLAM
// estimate, which repeats 4 timestamps (test/eval/data/README.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "hdvio/eval/alignment.h"
#include "hdvio/eval/association.h"
#include "hdvio/eval/pose_errors.h"
#include "hdvio/eval/statistics.h"
#include "hdvio/eval/trajectory_io.h"

namespace hdvio::eval {
namespace {

const std::string kDir = std::string(HDVIO_DATA_DIR) + "/reference_metrics";

class EvalEvoReference : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(kDir + "/KITTI_00_gt.txt"))
      GTEST_SKIP() << "reference data missing: " << kDir;
    gt_ = readTrajectory(kDir + "/KITTI_00_gt.txt");
    est_ = readTrajectory(kDir + "/KITTI_00_ORB.txt");
  }
  Trajectory gt_, est_;
};

// Relative tolerance against evo's own numbers: the metrics are meant to equal evo's.
void expectRelNear(double actual, double expected) {
  EXPECT_NEAR(actual, expected, 1e-6 * std::abs(expected)) << "expected " << expected;
}

TEST_F(EvalEvoReference, FilesAreKittiWithEqualLength) {
  EXPECT_FALSE(gt_.has_timestamps);
  EXPECT_EQ(gt_.size(), 4541u);
  EXPECT_EQ(est_.size(), 4541u);
}

TEST_F(EvalEvoReference, ApeTranslationWithSe3Alignment) {
  AssociationOptions assoc;
  assoc.mode = AssociationMode::kIndex;
  const AssociatedPair pair = associate(gt_, est_, assoc);
  const SimilarityTransform T = computeAlignment(AlignmentType::kSE3, pair.ref, pair.est, -1);
  EXPECT_DOUBLE_EQ(T.s, 1.0);
  const ErrorStatistics s =
      computeStatistics(absoluteErrors(pair.ref, applyAlignment(T, pair.est)).translation);
  expectRelNear(s.rmse, 1.3034497145650266);
  expectRelNear(s.mean, 1.1569971285389768);
  expectRelNear(s.median, 1.065624769555848);
  expectRelNear(s.max, 3.587949120678954);
  expectRelNear(s.min, 0.06931322021483087);
}

TEST_F(EvalEvoReference, RpeTranslationDelta10Meters) {
  EvoRpeOptions rpe;
  rpe.delta = 10.0;
  rpe.unit = DeltaUnit::kMeters;
  const RelativeErrors r = evoRelativeErrors(gt_, est_, rpe);
  const ErrorStatistics s = computeStatistics(r.translation);
  expectRelNear(s.rmse, 0.22626134329310163);
  expectRelNear(s.mean, 0.16901737200653275);
  expectRelNear(s.max, 1.2722090778658726);
}

// evo_ape euroc V102_groundtruth.csv V102.txt -a (evo 26d0953, test/eval/data/README.md):
// timestamp association (0.01 s, the 807 estimate poses against the longer ground truth), the 4
// repeated stamps kept, SE(3) Umeyama alignment, APE translation part.
TEST(EvalEvoV102, ApeWithRepeatedEstimateStamps) {
  const std::string dir = std::string(HDVIO_SOURCE_DIR) + "/test/eval/data";
  const Trajectory gt = readTrajectory(dir + "/evo_V102_groundtruth_excerpt.csv");
  const Trajectory est = readTrajectory(dir + "/evo_V102_ORB.txt");
  EXPECT_EQ(est.size(), 807u);
  EXPECT_EQ(est.repeated_stamps, 4u);
  EXPECT_EQ(gt.repeated_stamps, 0u);
  AssociationOptions assoc;
  assoc.mode = AssociationMode::kTimestamp;
  assoc.max_time_diff_s = 0.01;
  const AssociatedPair pair = associate(gt, est, assoc);
  EXPECT_EQ(pair.est.size(), 798u);  // "Found 798 of max. 807 possible matching timestamps"
  const SimilarityTransform T = computeAlignment(AlignmentType::kSE3, pair.ref, pair.est, -1);
  const ErrorStatistics s =
      computeStatistics(absoluteErrors(pair.ref, applyAlignment(T, pair.est)).translation);
  // evo's stats.json, to 1e-5 m on the RMSE.
  EXPECT_NEAR(s.rmse, 0.09172711520685754, 1e-5);
  EXPECT_NEAR(s.mean, 0.08152162194619848, 1e-5);
  EXPECT_NEAR(s.max, 0.2558167338139715, 1e-5);
  EXPECT_NEAR(s.min, 0.0026199870973830325, 1e-5);
}

}  // namespace
}  // namespace hdvio::eval
