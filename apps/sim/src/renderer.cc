#include "hdvio/sim/renderer.h"

#include <cmath>

#include "hdvio/core/error.h"

namespace hdvio::sim {
namespace {

inline float bilinear(const cv::Mat& img, double u, double v) {
  u = std::clamp(u, 0.0, img.cols - 1.000001);
  v = std::clamp(v, 0.0, img.rows - 1.000001);
  const int x = static_cast<int>(u), y = static_cast<int>(v);
  const float fx = static_cast<float>(u - x), fy = static_cast<float>(v - y);
  const float* r0 = img.ptr<float>(y) + x;
  const float* r1 = img.ptr<float>(y + 1) + x;
  return (1.0f - fy) * ((1.0f - fx) * r0[0] + fx * r0[1]) + fy * ((1.0f - fx) * r1[0] + fx * r1[1]);
}

}  // namespace

Renderer::Renderer(const Scene& scene, const CameraModel& camera) : scene_(scene), camera_(camera) {
  const int w = camera.width(), h = camera.height();
  rays_.resize(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool converged = false;
      const Vec3 bearing = camera.unproject(Eigen::Vector2d(x, y), &converged);
      // z = 1 so that the hit distance is the camera depth; no ray where distortion folds.
      rays_[static_cast<size_t>(y) * w + x] =
          converged ? Vec3(bearing / bearing.z()) : Vec3(0.0, 0.0, 0.0);  // renders as 0
    }
  focal_ = camera.focalLength();
}

float Renderer::sampleFace(int face, double u, double v, double footprint) const {
  const std::vector<cv::Mat>& levels = scene_.mipLevels(face);
  if (footprint <= 1.0) return bilinear(levels[0], u, v);
  const double lod = std::min(std::log2(footprint), static_cast<double>(levels.size() - 1));
  const int l0 = static_cast<int>(lod);
  const double frac = lod - l0;
  const double s0 = std::ldexp(1.0, -l0);
  const float a = bilinear(levels[l0], u * s0, v * s0);
  if (l0 + 1 >= static_cast<int>(levels.size()) || frac <= 0.0) return a;
  const float b = bilinear(levels[l0 + 1], u * s0 * 0.5, v * s0 * 0.5);
  return static_cast<float>((1.0 - frac) * a + frac * b);
}

void Renderer::render(const Pose& T_WC, cv::Mat* image, cv::Mat* depth) const {
  const Vec3 o = T_WC.p;
  const Vec3& lo = scene_.roomMin();
  const Vec3& hi = scene_.roomMax();
  if ((o.array() <= lo.array()).any() || (o.array() >= hi.array()).any())
    throw InputError("", 0, "renderer: camera is outside the room");
  const Mat3 R = T_WC.R();
  const int w = camera_.width(), h = camera_.height();
  image->create(h, w, CV_32F);
  if (depth) depth->create(h, w, CV_32F);
  const double inv_texel = 1.0 / scene_.texel();
  // Gates: rays in each gate's frame (o_G fixed per frame, d_G = R_GC * ray per pixel), and a
  // conservative box on the normalized image plane around each gate's bounding sphere so that
  // most pixels skip the gate test.
  struct GateView {
    const Gate* gate;
    Vec3 origin;
    Mat3 R_GC;
    double x0, x1, y0, y1;
  };
  std::vector<GateView> gate_views;
  for (const Gate& g : scene_.gates()) {
    const Vec3 c = R.transpose() * (g.center - o);
    const double r = std::sqrt(2.0 * g.outer_half * g.outer_half + g.half_depth * g.half_depth);
    if (c.z() + r <= 0.0) continue;  // entirely behind the camera
    GateView v{&g, g.R_WG.transpose() * (o - g.center), g.R_WG.transpose() * R, -1e300, 1e300, -1e300, 1e300};
    if (c.z() - r > 1e-3) {
      const double zs[2] = {c.z() - r, c.z() + r};
      v.x0 = v.y0 = 1e300;
      v.x1 = v.y1 = -1e300;
      for (double z : zs)
        for (double sx : {-r, r}) {
          v.x0 = std::min(v.x0, (c.x() + sx) / z);
          v.x1 = std::max(v.x1, (c.x() + sx) / z);
          v.y0 = std::min(v.y0, (c.y() + sx) / z);
          v.y1 = std::max(v.y1, (c.y() + sx) / z);
        }
    }
    gate_views.push_back(v);
  }

  for (int y = 0; y < h; ++y) {
    float* out = image->ptr<float>(y);
    float* dout = depth ? depth->ptr<float>(y) : nullptr;
    for (int x = 0; x < w; ++x) {
      const Vec3& rc = rays_[static_cast<size_t>(y) * w + x];
      if (rc.z() == 0.0) {
        out[x] = 0.0f;
        if (dout) dout[x] = 0.0f;
        continue;
      }
      const Vec3 d = R * rc;
      // Exit distance through the box along each axis; the smallest wins.
      double t = 1e300;
      int face = 0;
      for (int a = 0; a < 3; ++a) {
        if (d[a] > 0.0) {
          const double ta = (hi[a] - o[a]) / d[a];
          if (ta < t) { t = ta; face = 2 * a + 1; }
        } else if (d[a] < 0.0) {
          const double ta = (lo[a] - o[a]) / d[a];
          if (ta < t) { t = ta; face = 2 * a; }
        }
      }
      float value = 0.0f;
      bool gate_hit = false;
      for (const GateView& g : gate_views) {
        if (rc.x() < g.x0 || rc.x() > g.x1 || rc.y() < g.y0 || rc.y() > g.y1) continue;
        float gate_value = 0.0f;
        const double tg = Scene::intersectGate(*g.gate, g.origin, g.R_GC * rc, t, &gate_value);
        if (tg > 0.0) {
          t = tg;
          value = gate_value;
          gate_hit = true;
        }
      }
      if (!gate_hit) {
        const int a = face / 2, b = (a + 1) % 3, c = (a + 2) % 3;
        const double u = (o[b] + t * d[b] - lo[b]) * inv_texel;
        const double v = (o[c] + t * d[c] - lo[c]) * inv_texel;
        // Pixel footprint on the face in texels: distance / (focal * cos(incidence)) per pixel.
        const double d2 = d.squaredNorm();
        const double footprint = t * d2 / (focal_ * std::abs(d[a])) * inv_texel;
        value = sampleFace(face, u, v, footprint);
      }
      out[x] = value;
      if (dout) dout[x] = static_cast<float>(t);  // rays have z = 1: t is the camera depth
    }
  }
}

}  // namespace hdvio::sim
