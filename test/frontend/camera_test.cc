#include <gtest/gtest.h>

#include "hdvio/core/error.h"
#include "hdvio/frontend/camera.h"

namespace hdvio::frontend {
namespace {

Camera eurocCamera() {
  return Camera(752, 480, 458.654, 457.296, 367.215, 248.375, DistortionModel::kRadialTangential,
                {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
}
Camera fisheyeCamera() {
  return Camera(640, 480, 300.0, 300.0, 320.0, 240.0, DistortionModel::kEquidistant,
                {0.003, 0.02, -0.01, 0.002});
}

TEST(FrontendCamera, UnprojectInvertsProject) {
  for (const Camera& cam : {eurocCamera(), fisheyeCamera()}) {
    for (double u = 10; u < cam.width(); u += 73) {
      for (double v = 10; v < cam.height(); v += 59) {
        const Vec3 f = cam.unproject(Vec2(u, v));
        EXPECT_NEAR(f.norm(), 1.0, 1e-12);
        Vec2 px;
        ASSERT_TRUE(cam.project(2.5 * f, &px));
        EXPECT_NEAR(px.x(), u, 1e-6);
        EXPECT_NEAR(px.y(), v, 1e-6);
      }
    }
  }
}

TEST(FrontendCamera, ProjectionJacobianMatchesFiniteDifferences) {
  for (const Camera& cam : {eurocCamera(), fisheyeCamera()}) {
    for (const Vec3& p : {Vec3(0.4, -0.3, 2.0), Vec3(-1.1, 0.6, 1.5), Vec3(0.01, 0.02, 3.0)}) {
      Vec2 px;
      Mat23 J;
      ASSERT_TRUE(cam.project(p, &px, &J));
      for (int k = 0; k < 3; ++k) {
        Vec3 d = Vec3::Zero();
        d[k] = 1e-6;
        Vec2 a, b;
        cam.project(p + d, &a);
        cam.project(p - d, &b);
        const Vec2 numeric = (a - b) / 2e-6;
        EXPECT_NEAR((numeric - J.col(k)).norm(), 0.0, 1e-4 * (1.0 + numeric.norm()));
      }
    }
  }
}

TEST(FrontendCamera, DistortionIsRealOnEuroc) {
  // Corners of the EuRoC image bend by tens of pixels; undistorting points must account for it.
  const Camera cam = eurocCamera();
  const Vec3 f = cam.unproject(Vec2(5, 5));
  const Vec2 pinhole(458.654 * f.x() / f.z() + 367.215, 457.296 * f.y() / f.z() + 248.375);
  EXPECT_GT((pinhole - Vec2(5, 5)).norm(), 30.0);
}

TEST(FrontendCamera, PointsBehindAreNotProjected) {
  Vec2 px;
  EXPECT_FALSE(eurocCamera().project(Vec3(0.1, 0.1, -1.0), &px));
}

TEST(FrontendCamera, RejectsBadCalibration) {
  EXPECT_THROW(Camera(0, 480, 400, 400, 300, 200), InputError);
  EXPECT_THROW(Camera(640, 480, -400, 400, 300, 200), InputError);
  EXPECT_THROW(Camera(640, 480, 400, 400, 300, 200, DistortionModel::kRadialTangential, {0.1}),
               InputError);
}

}  // namespace
}  // namespace hdvio::frontend
