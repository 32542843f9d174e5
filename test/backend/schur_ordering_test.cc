// Eliminating exactly the landmarks first (OptimizerOptions::eliminate_first) changes only how
// Ceres solves the normal equations, not the solution: a small bundle adjustment converges to
// the same estimate with and without the explicit ordering.
#include <gtest/gtest.h>

#include <random>

#include "hdvio/backend/sliding_window_smoother.h"
#include "hdvio/factors/prior_factors.h"
#include "hdvio/factors/reprojection_factor.h"

namespace hdvio {
namespace {
using symbols::L;
using symbols::X;

Values solve(const FactorGraph& graph, const Values& initial, bool landmarks_first) {
  SmootherOptions options;
  options.optimizer.linear_solver = ceres::DENSE_SCHUR;
  options.optimizer.max_iterations = 50;
  options.optimizer.function_tolerance = 1e-12;
  if (landmarks_first) options.optimizer.eliminate_first = {L(0).letter()};
  SlidingWindowSmoother smoother(options);
  const auto result = smoother.update(graph, initial);
  EXPECT_TRUE(result.usable);
  return smoother.estimate();
}

TEST(SchurOrdering, LandmarksFirstGivesTheSameSolution) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  const CameraModel camera(320, 240, 300.0, 300.0, 160.0, 120.0);
  const Pose T_BC;  // camera = body
  FactorGraph graph;
  Values initial;
  std::vector<Pose> poses;
  for (int k = 0; k < 5; ++k) {
    // Cameras along x looking down +z (the camera frame's optical axis).
    const Pose T(Quat(Eigen::AngleAxisd(0.05 * k, Vec3::UnitY())), Vec3(0.3 * k, 0.0, 0.0));
    poses.push_back(T);
    initial.insertPose(X(k), Pose(T.q * Quat(Eigen::AngleAxisd(0.01, Vec3::UnitX())),
                                  T.p + Vec3(0.02, -0.01, 0.01)));
    if (k < 2)  // two fixed poses fix the gauge and the scale
      graph.add(std::make_shared<PosePrior>(X(k), T, NoiseModel::isotropic(6, 1e-3)));
  }
  for (int j = 0; j < 30; ++j) {
    const Vec3 p(-1.0 + 0.1 * j + 0.05 * n(rng), 0.4 * n(rng), 4.0 + n(rng));
    initial.insertVector(L(j), p + 0.05 * Vec3(n(rng), n(rng), n(rng)));
    for (int k = 0; k < 5; ++k) {
      const Vec3 p_C = poses[k].inverse() * p;
      Vec2 uv;
      ASSERT_TRUE(camera.project(p_C, &uv));
      uv += 0.5 * Vec2(n(rng), n(rng));
      graph.add(std::make_shared<ReprojectionFactor>(X(k), L(j), uv, camera, T_BC, pixelNoise(0.5)));
    }
  }
  const Values automatic = solve(graph, initial, false);
  const Values landmarks_first = solve(graph, initial, true);
  for (Key k : automatic.keys()) {
    const Eigen::VectorXd d = landmarks_first.minus(k, automatic);
    EXPECT_LT(d.norm(), 1e-6) << k.str();
  }
  // And the solution is a real one: the cost fell to the noise level (0.5 chi-square with
  // 312 residuals and 108 free parameters: about 100 expected; the start is far above).
  const auto cost = [&](const Values& v) {
    double c = 0.0;
    for (const auto& f : graph) c += f->error(v);
    return c;
  };
  EXPECT_GT(cost(initial), 1000.0);
  EXPECT_LT(cost(landmarks_first), 200.0);
}

}  // namespace
}  // namespace hdvio
