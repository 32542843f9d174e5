// Rendering: projection agrees with the image (< 0.5 px), views are photometrically
// consistent under the true motion, landmark tracks sit on the rendered surfaces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "hdvio/sim/renderer.h"
#include "hdvio/sim/simulator.h"
#include "sim_test_util.h"

namespace hdvio::sim {
namespace {

CameraCalibration distortedCamera() {
  CameraCalibration c;
  c.width = 320;
  c.height = 240;
  c.fu = 300.0;
  c.fv = 295.0;
  c.cu = 161.3;
  c.cv = 118.7;
  c.distortion = DistortionModel::kRadialTangential;
  c.distortion_coefficients = {-0.25, 0.07, 0.001, -0.0005};
  return c;
}

// Camera at `position` looking along `forward` (world), image x to the right of it.
Pose lookingAlong(const Vec3& position, const Vec3& forward) {
  const Vec3 z = forward.normalized();
  const Vec3 x = z.cross(Vec3::UnitZ()).normalized();
  Mat3 R;
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  return Pose(R, position);
}

TEST(SimRender, KnownPointProjectsWhereTheImageShowsIt) {
  const Vec3 lo(-3.0, -3.0, 0.0), hi(3.0, 3.0, 3.0);
  const double texel = 0.004;
  std::array<cv::Mat, kNumFaces> tex;
  for (int f = 0; f < kNumFaces; ++f) tex[f] = cv::Mat(Scene::faceSize(lo, hi, texel, f), CV_32F, cv::Scalar(200.0f));
  // A dark Gaussian dot (sigma 1.5 cm) on the wall x = +3 (face 1: columns along y, rows along z).
  const Vec3 marker(3.0, 0.37, 1.62);
  const double sigma = 0.015 / texel;
  const double mu = (marker.y() - lo.y()) / texel, mv = (marker.z() - lo.z()) / texel;
  for (int r = 0; r < tex[1].rows; ++r)
    for (int c = 0; c < tex[1].cols; ++c) {
      const double d2 = (c - mu) * (c - mu) + (r - mv) * (r - mv);
      tex[1].at<float>(r, c) -= static_cast<float>(150.0 * std::exp(-0.5 * d2 / (sigma * sigma)));
    }
  const Scene scene(lo, hi, texel, tex);
  const CameraModel camera = CameraModel::fromCalibration(distortedCamera());
  const Renderer renderer(scene, camera);

  int checked = 0;
  double worst = 0.0;
  // Views from different places and angles so the dot falls near the centre and the
  // strongly distorted corners.
  for (const Vec3& from : {Vec3(1.2, 0.0, 1.5), Vec3(0.5, -0.8, 1.0), Vec3(1.8, 1.0, 2.2)}) {
    for (const Vec3& aim : {Vec3(0, 0, 0), Vec3(0, 0.6, 0.35), Vec3(0, -0.5, -0.3), Vec3(0, 0.45, -0.4)}) {
      const Pose T_WC = lookingAlong(from, marker - from + aim);
      Eigen::Vector2d uv;
      ASSERT_TRUE(camera.project(T_WC.inverse() * marker, &uv));
      if (uv.x() < 15 || uv.y() < 15 || uv.x() > camera.width() - 16 || uv.y() > camera.height() - 16) continue;
      cv::Mat image;
      renderer.render(T_WC, &image);
      double sw = 0.0, su = 0.0, sv = 0.0;
      for (int y = static_cast<int>(uv.y()) - 12; y <= static_cast<int>(uv.y()) + 12; ++y)
        for (int x = static_cast<int>(uv.x()) - 12; x <= static_cast<int>(uv.x()) + 12; ++x) {
          const double w = std::max(0.0, 200.0 - image.at<float>(y, x) - 1.0);
          sw += w;
          su += w * x;
          sv += w * y;
        }
      ASSERT_GT(sw, 100.0);
      const double err = std::hypot(su / sw - uv.x(), sv / sw - uv.y());
      worst = std::max(worst, err);
      EXPECT_LT(err, 0.5) << "view from " << from.transpose() << " aim " << aim.transpose() << " at pixel "
                          << uv.transpose();
      ++checked;
    }
  }
  std::printf("marker centroid vs projection: worst %.3f px over %d views\n", worst, checked);
  EXPECT_GE(checked, 8);
}

TEST(SimRender, GatesOccludeTheRoomAndLandmarks) {
  const Vec3 lo(-3.0, -3.0, 0.0), hi(3.0, 3.0, 3.0);
  const double texel = 0.02;
  std::array<cv::Mat, kNumFaces> tex;
  for (int f = 0; f < kNumFaces; ++f) tex[f] = cv::Mat(Scene::faceSize(lo, hi, texel, f), CV_32F, cv::Scalar(100.0f));
  Gate gate;
  gate.center = Vec3(1.5, 0.0, 1.5);  // R_WG = identity: normal along +x
  const Scene scene(lo, hi, texel, tex, {gate});
  CameraCalibration cal = distortedCamera();
  const CameraModel camera = CameraModel::fromCalibration(cal);
  const Renderer renderer(scene, camera);
  const Pose T_WC = lookingAlong(Vec3(-2.0, 0.0, 1.5), Vec3::UnitX());
  cv::Mat image, depth;
  renderer.render(T_WC, &image, &depth);
  auto pixelOf = [&](const Vec3& p_W) {
    Eigen::Vector2d uv;
    EXPECT_TRUE(camera.project(T_WC.inverse() * p_W, &uv));
    EXPECT_TRUE(camera.inImage(uv));
    uv = uv.cwiseMax(0.0).cwiseMin(Eigen::Vector2d(camera.width() - 1, camera.height() - 1));
    return cv::Point(static_cast<int>(std::lround(uv.x())), static_cast<int>(std::lround(uv.y())));
  };
  // Through the opening: the far wall (x = 3) at depth 5.
  const cv::Point hole = pixelOf(Vec3(3.0, 0.1, 1.6));
  EXPECT_NEAR(depth.at<float>(hole), 5.0, 1e-3);
  EXPECT_NEAR(image.at<float>(hole), 100.0, 1e-3);
  // On the frame (top bar centre): the gate's front face at x = 1.5 - half_depth.
  const double bar = gate.inner_half + 0.5 * (gate.outer_half - gate.inner_half);
  const cv::Point on_bar = pixelOf(Vec3(1.5 - gate.half_depth, 0.0, 1.5 + bar));
  EXPECT_NEAR(depth.at<float>(on_bar), 3.5 - gate.half_depth, 0.02);
  // Landmarks on the wall behind the bar are hidden, behind the opening visible.
  EXPECT_TRUE(scene.segmentBlocked(T_WC.p, Vec3(3.0, 0.0, 1.5 + bar * 5.0 / 3.5)));
  EXPECT_FALSE(scene.segmentBlocked(T_WC.p, Vec3(3.0, 0.1, 1.6)));
}

TEST(SimRender, ConsecutiveFramesArePhotometricallyConsistent) {
  SimConfig c = testing::smallVisualConfig();
  c.camera.distortion = DistortionModel::kRadialTangential;
  c.camera.distortion_coefficients = {-0.1, 0.02, 0.0005, 0.0003};
  const Simulator sim(c);
  const Renderer renderer(*sim.scene(), *sim.camera());
  const CameraModel& cam = *sim.camera();
  const Pose A = sim.cameraPose(0.3), B = sim.cameraPose(0.4);
  cv::Mat ia, da, ib;
  renderer.render(A, &ia, &da);
  renderer.render(B, &ib);
  const Pose T_BA = B.inverse() * A;
  std::vector<double> warped, unwarped;
  for (int y = 4; y < cam.height() - 4; ++y)
    for (int x = 4; x < cam.width() - 4; ++x) {
      bool converged = false;
      const Vec3 bearing = cam.unproject(Eigen::Vector2d(x, y), &converged);
      ASSERT_TRUE(converged);
      const Vec3 ray = bearing / bearing.z();  // the depth map holds camera z
      Eigen::Vector2d uv;
      if (!cam.project(T_BA * (ray * da.at<float>(y, x)), &uv)) continue;
      if (uv.x() < 0 || uv.y() < 0 || uv.x() > cam.width() - 2 || uv.y() > cam.height() - 2) continue;
      cv::Mat patch;
      cv::getRectSubPix(ib, cv::Size(1, 1), cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y())), patch);
      warped.push_back(std::abs(ia.at<float>(y, x) - patch.at<float>(0, 0)));
      unwarped.push_back(std::abs(ia.at<float>(y, x) - ib.at<float>(y, x)));
    }
  ASSERT_GT(warped.size(), 0.7 * cam.width() * cam.height());
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  const double mw = median(warped), mu = median(unwarped);
  std::printf("median |I_A - I_B(warp)| = %.2f gray levels (without motion compensation %.2f)\n", mw, mu);
  EXPECT_LT(mw, 2.0);
  EXPECT_GT(mu, 4.0 * mw);
}

TEST(SimRender, LandmarkTracksLieOnTheRenderedSurfaces) {
  const Simulator sim(testing::smallVisualConfig());
  const SimulationResult r = sim.simulate();
  const Sequence& seq = r.sequence;
  ASSERT_GT(seq.landmark_observations.size(), 300u);
  const Renderer renderer(*sim.scene(), *sim.camera());
  Timestamp rendered_at = -1;
  cv::Mat image, depth;
  for (const LandmarkObservation& o : seq.landmark_observations) {
    const double time = secondsBetween(sim.config().start_time_ns, o.t);
    const Pose T_WC = sim.cameraPose(time);
    if (o.t != rendered_at) {
      renderer.render(T_WC, &image, &depth);
      rendered_at = o.t;
    }
    const Vec3 p_C = T_WC.inverse() * seq.landmarks.at(o.landmark_id);
    Eigen::Vector2d uv;
    ASSERT_TRUE(sim.camera()->project(p_C, &uv));
    EXPECT_LT(std::hypot(uv.x() - o.u, uv.y() - o.v), 1e-9);
    // The depth map around the pixel contains the landmark's depth (it is the visible surface).
    const int x = static_cast<int>(std::lround(o.u)), y = static_cast<int>(std::lround(o.v));
    double best = 1e9;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = std::clamp(x + dx, 0, image.cols - 1), yy = std::clamp(y + dy, 0, image.rows - 1);
        best = std::min(best, std::abs(depth.at<float>(yy, xx) - p_C.z()));
      }
    EXPECT_LT(best, 0.02 * p_C.z()) << "landmark " << o.landmark_id;
  }
}

TEST(SimRender, ImageEffectsAreDeterministicAndAsConfigured) {
  SimConfig c = testing::smallVisualConfig();
  const Simulator clean(c);
  c.camera.noise_std = 4.0;
  c.camera.exposure_variation = 0.2;
  c.camera.exposure_period = 2.0;
  c.camera.motion_blur_samples = 4;
  c.camera.exposure_time = 0.02;
  const Simulator noisy(c);
  const cv::Mat a = noisy.renderFrame(0.5, 5), b = noisy.renderFrame(0.5, 5), base = clean.renderFrame(0.5, 5);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, base, cv::NORM_L1) / a.total(), 2.0);
  // Noise alone: the difference to the clean frame has the configured spread.
  c.camera.exposure_variation = 0.0;
  c.camera.motion_blur_samples = 1;
  const Simulator only_noise(c);
  cv::Mat diff;
  cv::Mat(only_noise.renderFrame(0.5, 5)).convertTo(diff, CV_64F);
  cv::Mat base64;
  base.convertTo(base64, CV_64F);
  cv::Scalar mean, stddev;
  cv::meanStdDev(diff - base64, mean, stddev);
  EXPECT_NEAR(stddev[0], 4.0, 0.4);  // 8-bit rounding adds ~0.3 in quadrature
}

}  // namespace
}  // namespace hdvio::sim
