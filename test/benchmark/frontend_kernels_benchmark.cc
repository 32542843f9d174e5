// Per-call cost of the frontend's patch kernels on a textured 752x480 image: warping a
// reference patch, aligning it (translation + offset, from 1.5 px away), and one sparse image
// alignment of 150 points (the image against itself, started 2 cm off).
// Run: hdvio_frontend_benchmarks --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "hdvio/frontend/patch_alignment.h"
#include "hdvio/frontend/pyramid.h"
#include "hdvio/frontend/sparse_image_alignment.h"

namespace hdvio::frontend {
namespace {

cv::Mat texturedImage() {
  cv::Mat noise(480, 752, CV_32F);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 2.0);
  cv::Mat img;
  cv::normalize(noise, noise, 0.0, 255.0, cv::NORM_MINMAX);
  noise.convertTo(img, CV_8U);
  return img;
}

const Pyramid& pyramid() {
  static const Pyramid p = buildPyramid(texturedImage(), 5);
  return p;
}

void BM_WarpPatch(benchmark::State& state) {
  Eigen::Matrix2d A;
  A << 1.05, 0.1, -0.08, 0.97;
  BorderedPatch patch;
  for (auto _ : state) {
    benchmark::DoNotOptimize(warpPatch(A, pyramid()[0], Vec2(300.3, 200.7), 0, 0, &patch));
    benchmark::DoNotOptimize(patch.data());
  }
}
BENCHMARK(BM_WarpPatch);

void BM_Align2D(benchmark::State& state) {
  BorderedPatch patch;
  warpPatch(Eigen::Matrix2d::Identity(), pyramid()[0], Vec2(300.3, 200.7), 0, 0, &patch);
  for (auto _ : state) {
    Vec2 px(301.8, 199.4);
    benchmark::DoNotOptimize(align2D(pyramid()[0], patch, 10, &px));
    benchmark::DoNotOptimize(px.data());
  }
}
BENCHMARK(BM_Align2D);

void BM_SparseAlignment150Points(benchmark::State& state) {
  const CameraModel camera(752, 480, 450.0, 450.0, 376.0, 240.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(40.0, 712.0), v(40.0, 440.0), depth(3.0, 8.0);
  std::vector<Vec3> points;
  for (int i = 0; i < 150; ++i)
    points.push_back(camera.unproject(Vec2(u(rng), v(rng))) * depth(rng));
  SparseAlignmentOptions options;
  const Pose start(Quat::Identity(), Vec3(0.02, -0.01, 0.0));
  for (auto _ : state) {
    const SparseAlignmentResult r =
        alignSparse(camera, pyramid(), points, pyramid(), start, std::nullopt, options);
    benchmark::DoNotOptimize(r.T_cur_ref.p.data());
  }
}
BENCHMARK(BM_SparseAlignment150Points);

}  // namespace
}  // namespace hdvio::frontend

BENCHMARK_MAIN();
