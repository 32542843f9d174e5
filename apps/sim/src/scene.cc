#include "hdvio/sim/scene.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <opencv2/imgproc.hpp>

#include "hdvio/core/error.h"

namespace hdvio::sim {
namespace {

int axisB(int face) { return (face / 2 + 1) % 3; }
int axisC(int face) { return (face / 2 + 2) % 3; }

// Smooth random field with features of size ~cell (m): uniform noise on a coarse grid, cubic
// upsampling.
cv::Mat valueNoise(cv::Size size, double texel, double cell, std::mt19937_64& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const int gw = static_cast<int>(std::ceil(size.width * texel / cell)) + 3;
  const int gh = static_cast<int>(std::ceil(size.height * texel / cell)) + 3;
  cv::Mat grid(gh, gw, CV_32F);
  for (int r = 0; r < gh; ++r)
    for (int c = 0; c < gw; ++c) grid.at<float>(r, c) = u(rng);
  cv::Mat out;
  cv::resize(grid, out, size, 0, 0, cv::INTER_CUBIC);
  return out;
}

void addDisc(cv::Mat& img, double cx, double cy, double radius, float amplitude) {
  const double edge = 1.5;  // texels of soft edge: keeps the disc band-limited
  const int x0 = std::max(0, static_cast<int>(cx - radius - edge - 1));
  const int x1 = std::min(img.cols - 1, static_cast<int>(cx + radius + edge + 1));
  const int y0 = std::max(0, static_cast<int>(cy - radius - edge - 1));
  const int y1 = std::min(img.rows - 1, static_cast<int>(cy + radius + edge + 1));
  for (int y = y0; y <= y1; ++y) {
    float* row = img.ptr<float>(y);
    for (int x = x0; x <= x1; ++x) {
      const double r = std::hypot(x - cx, y - cy);
      const double w = std::clamp((radius - r) / edge + 0.5, 0.0, 1.0);
      row[x] += static_cast<float>(w) * amplitude;
    }
  }
}

void addChecker(cv::Mat& img, double cx, double cy, double half, double cell, float amplitude) {
  const int x0 = std::max(0, static_cast<int>(cx - half)), x1 = std::min(img.cols - 1, static_cast<int>(cx + half));
  const int y0 = std::max(0, static_cast<int>(cy - half)), y1 = std::min(img.rows - 1, static_cast<int>(cy + half));
  for (int y = y0; y <= y1; ++y) {
    float* row = img.ptr<float>(y);
    for (int x = x0; x <= x1; ++x) {
      // Smoothed square wave (two texels of transition) rather than a hard step.
      const double sx = std::sin(M_PI * (x - cx) / cell), sy = std::sin(M_PI * (y - cy) / cell);
      const double s = std::tanh(2.0 * sx * cell / M_PI) * std::tanh(2.0 * sy * cell / M_PI);
      row[x] = static_cast<float>(row[x] * 0.2 + amplitude * s);
    }
  }
}

cv::Mat makeTexture(cv::Size size, double texel, std::mt19937_64& rng) {
  cv::Mat tex = cv::Mat::zeros(size, CV_32F);
  for (double cell = 1.6; cell >= 2.5 * texel; cell *= 0.5) {
    tex += valueNoise(size, texel, cell, rng) * static_cast<float>(std::pow(cell, 0.4));
  }
  const double area = size.area() * texel * texel;
  std::uniform_real_distribution<double> ux(0.0, size.width), uy(0.0, size.height), unit(0.0, 1.0);
  const int blobs = static_cast<int>(area * 3.0);
  for (int i = 0; i < blobs; ++i) {
    const double radius = std::exp(std::log(0.03) + unit(rng) * std::log(10.0)) / texel;
    const float amplitude = static_cast<float>((unit(rng) < 0.5 ? -1.0 : 1.0) * (0.6 + unit(rng)));
    addDisc(tex, ux(rng), uy(rng), radius, amplitude);
  }
  const int patches = static_cast<int>(area * 0.15) + 1;
  for (int i = 0; i < patches; ++i) {
    const double half = (0.15 + 0.3 * unit(rng)) / texel;
    const double cell = std::max(3.0, (0.04 + 0.08 * unit(rng)) / texel);
    addChecker(tex, ux(rng), uy(rng), half, cell, 1.5f);
  }
  cv::Scalar mean, stddev;
  cv::meanStdDev(tex, mean, stddev);
  const double brightness = 0.8 + 0.3 * unit(rng);  // faces lit differently
  tex = (tex - mean[0]) * (45.0 / std::max(1e-6, stddev[0]));
  tex = (tex + 128.0) * brightness;
  cv::max(tex, 8.0, tex);
  cv::min(tex, 247.0, tex);
  return tex;
}

}  // namespace

cv::Size Scene::faceSize(const Vec3& room_min, const Vec3& room_max, double texel, int face) {
  const Vec3 size = room_max - room_min;
  return cv::Size(static_cast<int>(std::ceil(size[axisB(face)] / texel)) + 1,
                  static_cast<int>(std::ceil(size[axisC(face)] / texel)) + 1);
}

Scene::Scene(const SceneConfig& config, const std::vector<GateConfig>& gates, std::uint64_t seed)
    : min_(config.room_min), max_(config.room_max), texel_(config.texel_size) {
  for (int f = 0; f < kNumFaces; ++f) {
    std::mt19937_64 rng(seed * 1000003 + 101 * f + 7);
    buildMips(f, makeTexture(faceSize(min_, max_, texel_, f), texel_, rng));
  }
  if (config.render_gates) {
    for (const GateConfig& g : gates) {
      Gate gate;
      gate.center = g.position;
      const Vec3 x(std::cos(g.yaw), std::sin(g.yaw), 0.0), z = Vec3::UnitZ();
      gate.R_WG.col(0) = x;
      gate.R_WG.col(1) = z.cross(x);
      gate.R_WG.col(2) = z;
      gate.inner_half = 0.5 * config.gate_inner_size;
      gate.outer_half = gate.inner_half + config.gate_border;
      gates_.push_back(gate);
    }
  }
}

Scene::Scene(const Vec3& room_min, const Vec3& room_max, double texel,
             const std::array<cv::Mat, kNumFaces>& textures, std::vector<Gate> gates)
    : min_(room_min), max_(room_max), texel_(texel), gates_(std::move(gates)) {
  for (int f = 0; f < kNumFaces; ++f) {
    if (textures[f].size() != faceSize(min_, max_, texel_, f) || textures[f].type() != CV_32F)
      throw std::invalid_argument("Scene: texture " + std::to_string(f) + " has the wrong size or type");
    buildMips(f, textures[f]);
  }
}

void Scene::buildMips(int face, const cv::Mat& level0) {
  std::vector<cv::Mat>& levels = mips_[face];
  levels.clear();
  levels.push_back(level0.clone());
  while (std::min(levels.back().cols, levels.back().rows) >= 8) {
    cv::Mat next;
    cv::pyrDown(levels.back(), next);
    levels.push_back(next);
  }
}

std::vector<Vec3> Scene::sampleSurfacePoints(int count, std::uint64_t seed) const {
  std::mt19937_64 rng(seed * 15485863 + 11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Vec3 size = max_ - min_;
  std::array<double, kNumFaces> cumulative{};
  double total = 0.0;
  for (int f = 0; f < kNumFaces; ++f) {
    total += size[axisB(f)] * size[axisC(f)];
    cumulative[f] = total;
  }
  std::vector<Vec3> points;
  points.reserve(count);
  for (int i = 0; i < count; ++i) {
    const double pick = unit(rng) * total;
    int f = 0;
    while (f < kNumFaces - 1 && pick > cumulative[f]) ++f;
    Vec3 p;
    const int a = f / 2;
    p[a] = (f % 2 == 0) ? min_[a] : max_[a];
    p[axisB(f)] = min_[axisB(f)] + unit(rng) * size[axisB(f)];
    p[axisC(f)] = min_[axisC(f)] + unit(rng) * size[axisC(f)];
    points.push_back(p);
  }
  return points;
}

double Scene::intersectGate(const Gate& g, const Vec3& og, const Vec3& dg, double t_max, float* intensity) {
  // Cheap rejection: the ray misses the gate's bounding sphere.
  const double radius2 = 2.0 * g.outer_half * g.outer_half + g.half_depth * g.half_depth;
  const double dd = dg.squaredNorm();
  if (og.cross(dg).squaredNorm() > radius2 * dd) return -1.0;
  const Vec3 half(g.half_depth, g.outer_half, g.outer_half);
  double t0 = -1e300, t1 = 1e300;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(dg[k]) < 1e-15) {
      if (std::abs(og[k]) > half[k]) return -1.0;
      continue;
    }
    double ta = (-half[k] - og[k]) / dg[k], tb = (half[k] - og[k]) / dg[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 < t1) || t1 <= 0.0) return -1.0;
  // Thin frame: solid where the entry (or exit) point lies outside the inner square.
  double t_hit = -1.0;
  Vec3 q;
  if (t0 > 0.0) {
    q = og + t0 * dg;
    if (std::max(std::abs(q.y()), std::abs(q.z())) >= g.inner_half) t_hit = t0;
  }
  if (t_hit < 0.0) {
    q = og + t1 * dg;
    if (std::max(std::abs(q.y()), std::abs(q.z())) >= g.inner_half) t_hit = t1;
  }
  if (t_hit <= 0.0 || t_hit >= t_max) return -1.0;
  // Diagonal stripes, like the checkered tape on racing gates.
  if (intensity) *intensity = static_cast<float>(128.0 + 100.0 * std::sin(2.0 * M_PI * (q.y() + q.z()) / 0.25));
  return t_hit;
}

double Scene::intersectGates(const Vec3& o, const Vec3& d, double t_max, float* intensity) const {
  double best = -1.0;
  for (const Gate& g : gates_) {
    float value = 0.0f;
    const double t = intersectGate(g, g.R_WG.transpose() * (o - g.center), g.R_WG.transpose() * d,
                                   best >= 0.0 ? best : t_max, &value);
    if (t > 0.0) {
      best = t;
      if (intensity) *intensity = value;
    }
  }
  return best;
}

bool Scene::segmentBlocked(const Vec3& a, const Vec3& b) const {
  if (gates_.empty()) return false;
  return intersectGates(a, b - a, 1.0 - 1e-6, nullptr) >= 0.0;
}

}  // namespace hdvio::sim
