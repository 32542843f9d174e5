// Camera projection: round trips, distortion Jacobians, closed-form special cases.
#include <gtest/gtest.h>

#include <random>

#include "hdvio/core/error.h"
#include "hdvio/factors/camera_model.h"
#include "test_support.h"

namespace hdvio {
namespace {

CameraModel makeCamera(DistortionModel model) {
  std::vector<double> k;
  if (model == DistortionModel::kRadialTangential) k = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  if (model == DistortionModel::kEquidistant) k = {-0.013, 0.021, -0.012, 0.003};
  return CameraModel(458.654, 457.296, 367.215, 248.375, model, k, 752, 480);
}

class CameraModels : public ::testing::TestWithParam<DistortionModel> {};

TEST_P(CameraModels, ProjectUnprojectRoundTrip) {
  const CameraModel cam = makeCamera(GetParam());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.6, 0.6), depth(0.5, 20.0);
  for (int i = 0; i < 200; ++i) {
    const double z = depth(rng);
    const Vec3 p(u(rng) * z, u(rng) * z, z);
    Vec2 uv;
    ASSERT_TRUE(cam.project(p, &uv));
    const Vec3 bearing = cam.unproject(uv);
    EXPECT_NEAR(bearing.norm(), 1.0, 1e-12);
    EXPECT_LT((bearing - p.normalized()).norm(), 1e-9) << "point " << p.transpose();
  }
}

TEST_P(CameraModels, ProjectionJacobianMatchesNumerical) {
  const CameraModel cam = makeCamera(GetParam());
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-0.6, 0.6), depth(0.5, 20.0);
  for (int i = 0; i < 100; ++i) {
    const double z = depth(rng);
    const Vec3 p(u(rng) * z, u(rng) * z, z);
    Vec2 uv;
    Mat23 J;
    ASSERT_TRUE(cam.project(p, &uv, &J));
    Mat23 numerical;
    const double h = 1e-6;
    for (int d = 0; d < 3; ++d) {
      Vec3 dp = Vec3::Zero();
      dp[d] = h;
      Vec2 up, um;
      cam.project(p + dp, &up);
      cam.project(p - dp, &um);
      numerical.col(d) = (up - um) / (2 * h);
    }
    EXPECT_LT((J - numerical).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, J.cwiseAbs().maxCoeff()));
  }
}

INSTANTIATE_TEST_SUITE_P(AllModels, CameraModels,
                         ::testing::Values(DistortionModel::kNone, DistortionModel::kRadialTangential,
                                           DistortionModel::kEquidistant));

TEST(CameraModel, ClosedFormCases) {
  // Pinhole: u = fu x/z + cu.
  const CameraModel pin = makeCamera(DistortionModel::kNone);
  Vec2 uv;
  ASSERT_TRUE(pin.project(Vec3(1.0, -2.0, 4.0), &uv));
  EXPECT_NEAR(uv.x(), 458.654 * 0.25 + 367.215, 1e-9);
  EXPECT_NEAR(uv.y(), 457.296 * -0.5 + 248.375, 1e-9);
  // Ideal equidistant (k = 0): a ray 45 degrees off-axis lands at f * pi/4 from the centre.
  const CameraModel fish(300.0, 300.0, 320.0, 240.0, DistortionModel::kEquidistant, {0, 0, 0, 0});
  ASSERT_TRUE(fish.project(Vec3(1.0, 0.0, 1.0), &uv));
  EXPECT_NEAR(uv.x() - 320.0, 300.0 * M_PI / 4.0, 1e-9);
  // Radial-tangential with only k1: x_d = x (1 + k1 r^2).
  const CameraModel rad(100.0, 100.0, 0.0, 0.0, DistortionModel::kRadialTangential, {0.1, 0, 0, 0});
  ASSERT_TRUE(rad.project(Vec3(0.5, 0.0, 1.0), &uv));
  EXPECT_NEAR(uv.x(), 100.0 * 0.5 * (1.0 + 0.1 * 0.25), 1e-9);
  // Behind the camera.
  EXPECT_FALSE(pin.project(Vec3(0.0, 0.0, -1.0), &uv));
}

TEST(CameraModel, RejectsBadIntrinsics) {
  EXPECT_THROW(CameraModel(0.0, 1.0, 0, 0, DistortionModel::kNone, {}), InputError);
  EXPECT_THROW(CameraModel(1.0, 1.0, 0, 0, DistortionModel::kRadialTangential, {0.1, 0.2}), InputError);
  CameraCalibration calib;
  calib.fu = calib.fv = 400.0;
  calib.distortion = DistortionModel::kEquidistant;
  calib.distortion_coefficients = {0.1, 0.0, 0.0, std::nan("")};
  EXPECT_THROW(CameraModel::fromCalibration(calib), InputError);
}

}  // namespace
}  // namespace hdvio
