// The one camera model: Jacobians against central differences, project/unproject and
// distort/undistort round trips, closed-form cases, the minimum depth, in-image borders at
// pyramid levels, and bad calibrations.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hdvio/core/camera_model.h"
#include "hdvio/core/error.h"

namespace hdvio {
namespace {

CameraModel makeCamera(DistortionModel model) {
  std::vector<double> k;
  if (model == DistortionModel::kRadialTangential) k = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  if (model == DistortionModel::kEquidistant) k = {-0.013, 0.021, -0.012, 0.003};
  return CameraModel(752, 480, 458.654, 457.296, 367.215, 248.375, model, k);
}

// Points 0.5-20 m ahead, up to 31 degrees off the axis in x and y.
std::vector<Vec3> pointsAhead(unsigned seed, int n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.6, 0.6), depth(0.5, 20.0);
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i) {
    const double z = depth(rng);
    points.emplace_back(u(rng) * z, u(rng) * z, z);
  }
  return points;
}

class CameraModels : public ::testing::TestWithParam<DistortionModel> {};

TEST_P(CameraModels, ProjectUnprojectRoundTrip) {
  const CameraModel cam = makeCamera(GetParam());
  for (const Vec3& p : pointsAhead(5, 200)) {
    Vec2 uv;
    ASSERT_TRUE(cam.project(p, &uv));
    bool converged = false;
    const Vec3 bearing = cam.unproject(uv, &converged);
    EXPECT_TRUE(converged);
    EXPECT_NEAR(bearing.norm(), 1.0, 1e-12);
    EXPECT_LT((bearing - p.normalized()).norm(), 1e-9) << "point " << p.transpose();
  }
}

TEST_P(CameraModels, PixelGridSurvivesUnprojectProject) {
  // Pixel -> bearing -> pixel over the whole image, corners included (where the EuRoC
  // distortion moves points by tens of pixels).
  const CameraModel cam = makeCamera(GetParam());
  for (double u = 0; u < cam.width(); u += 37.5) {
    for (double v = 0; v < cam.height(); v += 29.5) {
      const Vec3 f = cam.unproject(Vec2(u, v));
      Vec2 px;
      ASSERT_TRUE(cam.project(2.5 * f, &px));
      EXPECT_LT((px - Vec2(u, v)).norm(), 1e-6) << u << " " << v;
    }
  }
}

TEST_P(CameraModels, ProjectionJacobianMatchesNumerical) {
  const CameraModel cam = makeCamera(GetParam());
  for (const Vec3& p : pointsAhead(6, 100)) {
    Vec2 uv;
    Mat23 J;
    ASSERT_TRUE(cam.project(p, &uv, &J));
    Mat23 numerical;
    const double h = 1e-6;
    for (int d = 0; d < 3; ++d) {
      Vec3 dp = Vec3::Zero();
      dp[d] = h;
      Vec2 up, um;
      ASSERT_TRUE(cam.project(p + dp, &up));
      ASSERT_TRUE(cam.project(p - dp, &um));
      numerical.col(d) = (up - um) / (2 * h);
    }
    EXPECT_LT((J - numerical).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, J.cwiseAbs().maxCoeff()));
  }
}

TEST_P(CameraModels, DistortionJacobianAndInverse) {
  const CameraModel cam = makeCamera(GetParam());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.8, 0.8);
  for (int i = 0; i < 100; ++i) {
    const Vec2 m(u(rng), u(rng));
    Mat2 J;
    const Vec2 md = cam.distort(m, &J);
    const double h = 1e-7;
    Mat2 numerical;
    for (int d = 0; d < 2; ++d) {
      Vec2 dm = Vec2::Zero();
      dm[d] = h;
      numerical.col(d) = (cam.distort(m + dm) - cam.distort(m - dm)) / (2 * h);
    }
    EXPECT_LT((J - numerical).cwiseAbs().maxCoeff(), 1e-7) << m.transpose();
    bool converged = false;
    const Vec2 back = cam.undistort(md, &converged);
    EXPECT_TRUE(converged);
    EXPECT_LT((back - m).norm(), 1e-11) << m.transpose();
    EXPECT_LT((cam.distort(back) - md).norm(), CameraModel::kUndistortTolerance);
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
  const CameraModel fish(640, 480, 300.0, 300.0, 320.0, 240.0, DistortionModel::kEquidistant, {0, 0, 0, 0});
  ASSERT_TRUE(fish.project(Vec3(1.0, 0.0, 1.0), &uv));
  EXPECT_NEAR(uv.x() - 320.0, 300.0 * M_PI / 4.0, 1e-9);
  // On the axis the equidistant map is the identity (and finite).
  Mat2 J;
  EXPECT_EQ(fish.distort(Vec2(1e-9, 0.0), &J), Vec2(1e-9, 0.0));
  EXPECT_EQ(J, Mat2::Identity());
  // Radial-tangential with only k1: x_d = x (1 + k1 r^2).
  const CameraModel rad(200, 200, 100.0, 100.0, 0.0, 0.0, DistortionModel::kRadialTangential, {0.1, 0, 0, 0});
  ASSERT_TRUE(rad.project(Vec3(0.5, 0.0, 1.0), &uv));
  EXPECT_NEAR(uv.x(), 100.0 * 0.5 * (1.0 + 0.1 * 0.25), 1e-9);
  // The EuRoC image corner bends by tens of pixels: unproject really removes distortion.
  const CameraModel euroc = makeCamera(DistortionModel::kRadialTangential);
  const Vec3 f = euroc.unproject(Vec2(5, 5));
  const Vec2 pinhole(458.654 * f.x() / f.z() + 367.215, 457.296 * f.y() / f.z() + 248.375);
  EXPECT_GT((pinhole - Vec2(5, 5)).norm(), 30.0);
}

TEST(CameraModel, UndistortReportsWhereDistortionFolds) {
  // x_d = x (1 - 0.5 x^2) peaks at x_d = 0.544 (x = 0.816): nothing distorts to 0.7.
  const CameraModel cam(400, 400, 100.0, 100.0, 200.0, 200.0, DistortionModel::kRadialTangential,
                        {-0.5, 0.0, 0.0, 0.0});
  bool converged = true;
  cam.undistort(Vec2(0.7, 0.0), &converged);
  EXPECT_FALSE(converged);
  cam.undistort(Vec2(0.5, 0.0), &converged);
  EXPECT_TRUE(converged);
}

TEST(CameraModel, MinimumDepth) {
  const CameraModel cam = makeCamera(DistortionModel::kRadialTangential);
  const Vec2 untouched(-7.0, -7.0);
  Vec2 uv = untouched;
  EXPECT_TRUE(cam.project(Vec3(0.0, 0.0, CameraModel::kMinDepth), &uv));
  uv = untouched;
  EXPECT_FALSE(cam.project(Vec3(0.0, 0.0, 0.999 * CameraModel::kMinDepth), &uv));
  EXPECT_FALSE(cam.project(Vec3(0.1, 0.1, -1.0), &uv));
  EXPECT_FALSE(cam.project(Vec3(0.0, 0.0, std::nan("")), &uv));
  EXPECT_FALSE(cam.project(Vec3(std::nan(""), 0.0, 1.0), &uv));
  EXPECT_EQ(uv, untouched);
}

TEST(CameraModel, InImageBordersAtPyramidLevels) {
  // Half-open: [border, size_L - 1 - border) in level pixels, size_L = size >> L.
  const CameraModel cam(641, 480, 400.0, 400.0, 320.0, 240.0);
  const double eps = 1e-9;
  // Level 0, no border.
  EXPECT_TRUE(cam.inImage(Vec2(0.0, 0.0)));
  EXPECT_FALSE(cam.inImage(Vec2(-eps, 10.0)));
  EXPECT_FALSE(cam.inImage(Vec2(10.0, -eps)));
  EXPECT_TRUE(cam.inImage(Vec2(640.0 - eps, 479.0 - eps)));
  EXPECT_FALSE(cam.inImage(Vec2(640.0, 10.0)));
  EXPECT_FALSE(cam.inImage(Vec2(10.0, 479.0)));
  // Level 0, border 8.
  EXPECT_TRUE(cam.inImage(Vec2(8.0, 8.0), 8.0));
  EXPECT_FALSE(cam.inImage(Vec2(8.0 - eps, 100.0), 8.0));
  EXPECT_TRUE(cam.inImage(Vec2(632.0 - eps, 471.0 - eps), 8.0));
  EXPECT_FALSE(cam.inImage(Vec2(632.0, 100.0), 8.0));
  EXPECT_FALSE(cam.inImage(Vec2(100.0, 471.0), 8.0));
  // Level 1: 320 x 240 (641 >> 1 = 320, not 320.5): level u < 319 -> pixel u < 638.
  EXPECT_TRUE(cam.inImage(Vec2(638.0 - eps, 478.0 - eps), 0.0, 1));
  EXPECT_FALSE(cam.inImage(Vec2(638.0, 100.0), 0.0, 1));
  EXPECT_FALSE(cam.inImage(Vec2(100.0, 478.0), 0.0, 1));
  // Level 2 with a border of 2 level pixels: 160 x 120, level u in [2, 157) -> pixel [8, 628).
  EXPECT_TRUE(cam.inImage(Vec2(8.0, 8.0), 2.0, 2));
  EXPECT_FALSE(cam.inImage(Vec2(8.0 - eps, 100.0), 2.0, 2));
  EXPECT_TRUE(cam.inImage(Vec2(628.0 - eps, 468.0 - eps), 2.0, 2));
  EXPECT_FALSE(cam.inImage(Vec2(628.0, 100.0), 2.0, 2));
  EXPECT_FALSE(cam.inImage(Vec2(100.0, 468.0), 2.0, 2));
}

TEST(CameraModel, RejectsBadCalibration) {
  using D = DistortionModel;
  EXPECT_THROW(CameraModel(0, 480, 400, 400, 300, 200), InputError);
  EXPECT_THROW(CameraModel(640, -1, 400, 400, 300, 200), InputError);
  EXPECT_THROW(CameraModel(640, 480, 0.0, 400, 300, 200), InputError);
  EXPECT_THROW(CameraModel(640, 480, 400, -400, 300, 200), InputError);
  EXPECT_THROW(CameraModel(640, 480, std::nan(""), 400, 300, 200), InputError);
  EXPECT_THROW(CameraModel(640, 480, 400, 400, INFINITY, 200), InputError);
  EXPECT_THROW(CameraModel(640, 480, 400, 400, 300, 200, D::kRadialTangential, {0.1, 0.2}), InputError);
  EXPECT_THROW(CameraModel(640, 480, 400, 400, 300, 200, D::kEquidistant, {}), InputError);
  EXPECT_THROW(CameraModel(640, 480, 400, 400, 300, 200, D::kNone, {0.1, 0, 0, 0}), InputError);
  EXPECT_NO_THROW(CameraModel(640, 480, 400, 400, 300, 200, D::kEquidistant, {0.1, 0, 0, 0}));
  CameraCalibration calib;
  calib.width = 640;
  calib.height = 480;
  calib.fu = calib.fv = 400.0;
  calib.distortion = D::kEquidistant;
  calib.distortion_coefficients = {0.1, 0.0, 0.0, std::nan("")};
  calib.file = "cam0/sensor.yaml";
  try {
    CameraModel::fromCalibration(calib);
    ADD_FAILURE() << "a NaN coefficient was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "cam0/sensor.yaml");
    EXPECT_NE(e.problem().find("not finite"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hdvio
