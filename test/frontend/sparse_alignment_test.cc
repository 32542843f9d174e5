// Sparse image alignment recovers a known camera motion between two rendered images.
#include <gtest/gtest.h>

#include "hdvio/frontend/feature_detector.h"
#include "hdvio/frontend/sparse_image_alignment.h"
#include "synthetic_room.h"

namespace hdvio::frontend {
namespace {

struct AlignmentCase {
  Pose T_w_ref, T_w_cur;
  Pyramid ref, cur;
  std::vector<Vec3> points_ref;
};

AlignmentCase makeCase(const CameraModel& camera, const test::SyntheticRoom& room, const Pose& T_w_ref,
                       const Pose& T_w_cur) {
  AlignmentCase c{T_w_ref, T_w_cur, buildPyramid(room.render(camera, T_w_ref), 5),
                  buildPyramid(room.render(camera, T_w_cur), 5), {}};
  const FeatureGrid grid(camera.width(), camera.height(), 32);
  for (const Corner& k : detectCorners(c.ref, DetectorOptions(), grid,
                                       std::vector<bool>(grid.cells(), false))) {
    const Vec3 f = camera.unproject(k.px);
    c.points_ref.push_back(f / f.z() * room.depthAt(camera, T_w_ref, k.px));
  }
  return c;
}

double rotationErrorDeg(const Pose& a, const Pose& b) {
  return quatLog(a.q.conjugate() * b.q).norm() * 180.0 / M_PI;
}

TEST(FrontendSparseImageAlignment, RecoversKnownMotionFromIdentityGuess) {
  const CameraModel camera = CameraModel::fromCalibration(test::syntheticCalibration());
  const test::SyntheticRoom room;
  const Pose T_w_ref = test::lookingForward(Vec3(-1.0, 0.3, 1.4), 0.1, 0.25);
  // 6 cm and 2 degrees between the images: a fast 20 Hz frame-to-frame motion.
  const Pose T_w_cur = T_w_ref * Pose(quatExp(Vec3(0.02, -0.025, 0.01)), Vec3(0.04, -0.02, 0.04));
  const AlignmentCase c = makeCase(camera, room, T_w_ref, T_w_cur);
  ASSERT_GT(c.points_ref.size(), 80u);

  const Pose truth = T_w_cur.inverse() * T_w_ref;
  const SparseAlignmentResult r = alignSparse(camera, c.ref, c.points_ref, c.cur, Pose(),
                                              std::nullopt, SparseAlignmentOptions());
  ASSERT_TRUE(r.ok);
  EXPECT_GT(r.patches, 80);
  EXPECT_LT((r.T_cur_ref.p - truth.p).norm(), 0.005);  // m, of a 6 cm motion
  EXPECT_LT(rotationErrorDeg(r.T_cur_ref, truth), 0.05);
  // The identity guess is far off: the error must really have been reduced.
  EXPECT_GT(rotationErrorDeg(Pose(), truth), 1.5);
}

TEST(FrontendSparseImageAlignment, LargeRotationWithGyroPrior) {
  const CameraModel camera = CameraModel::fromCalibration(test::syntheticCalibration());
  const test::SyntheticRoom room;
  const Pose T_w_ref = test::lookingForward(Vec3(0.0, -1.0, 1.5), -0.2, 0.2);
  // 8 degrees of yaw in one image: beyond the basin of the coarsest level without a prior.
  const Pose T_w_cur = T_w_ref * Pose(quatExp(Vec3(0.02, 0.14, 0.0)), Vec3(0.03, 0.0, 0.02));
  const AlignmentCase c = makeCase(camera, room, T_w_ref, T_w_cur);
  const Pose truth = T_w_cur.inverse() * T_w_ref;
  // Gyro prior with a 0.3 degree error, used both as initial guess and as prior.
  const Quat prior = truth.q * quatExp(Vec3(0.003, -0.004, 0.002));
  const SparseAlignmentResult r = alignSparse(camera, c.ref, c.points_ref, c.cur,
                                              Pose(prior, Vec3::Zero()), prior,
                                              SparseAlignmentOptions());
  ASSERT_TRUE(r.ok);
  EXPECT_LT((r.T_cur_ref.p - truth.p).norm(), 0.005);
  EXPECT_LT(rotationErrorDeg(r.T_cur_ref, truth), 0.05);
}

TEST(FrontendSparseImageAlignment, ReportsFailureWithoutPoints) {
  const CameraModel camera = CameraModel::fromCalibration(test::syntheticCalibration());
  const Pyramid pyr = buildPyramid(cv::Mat(480, 752, CV_8UC1, cv::Scalar(128)), 5);
  const SparseAlignmentResult r =
      alignSparse(camera, pyr, {}, pyr, Pose(), std::nullopt, SparseAlignmentOptions());
  EXPECT_FALSE(r.ok);
}

}  // namespace
}  // namespace hdvio::frontend
