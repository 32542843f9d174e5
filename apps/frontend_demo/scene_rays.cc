#include "scene_rays.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hdvio {

RayHit castRayHit(const sim::Scene& scene, const Vec3& o, const Vec3& d) {
  RayHit hit;
  const Vec3& lo = scene.roomMin();
  const Vec3& hi = scene.roomMax();
  if ((o.array() <= lo.array()).any() || (o.array() >= hi.array()).any()) return hit;
  double t = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (d[a] > 0 && (hi[a] - o[a]) / d[a] < t) t = (hi[a] - o[a]) / d[a], hit.surface = 2 * a + 1;
    if (d[a] < 0 && (lo[a] - o[a]) / d[a] < t) t = (lo[a] - o[a]) / d[a], hit.surface = 2 * a;
  }
  hit.distance = t;
  const std::vector<sim::Gate>& gates = scene.gates();
  for (size_t i = 0; i < gates.size(); ++i) {
    const sim::Gate& g = gates[i];
    const double t_gate = sim::Scene::intersectGate(g, g.R_WG.transpose() * (o - g.center),
                                                    g.R_WG.transpose() * d, hit.distance, nullptr);
    if (t_gate > 0.0) hit.distance = t_gate, hit.surface = kGateSurface + static_cast<int>(i);
  }
  return hit;
}

double castRay(const sim::Scene& scene, const Vec3& o, const Vec3& d) {
  return castRayHit(scene, o, d).distance;
}

const char* cornerKindName(CornerKind k) {
  switch (k) {
    case CornerKind::kSurface: return "surface";
    case CornerKind::kCrease: return "crease";
    case CornerKind::kSlanted: return "slanted";
    case CornerKind::kOcclusion: return "occlusion";
    case CornerKind::kUnknown: break;
  }
  return "unknown";
}

CornerClass classifyCorner(const sim::Scene& scene, const CameraModel& camera, const Pose& T_WC,
                           const Vec2& px, int level, const CornerClassOptions& options) {
  CornerClass c;
  const auto hitAt = [&](const Vec2& uv) {
    bool converged = false;
    const Vec3 f = camera.unproject(uv, &converged);
    return converged ? castRayHit(scene, T_WC.p, T_WC.q * f.normalized()) : RayHit{};
  };
  c.centre = hitAt(px);
  if (!c.centre.valid()) return c;
  bool step = false, crease = false, occlusion = false;
  const double scale = std::ldexp(1.0, level);
  for (double radius : options.radii_level_px) {
    for (int k = 0; k < 8; ++k) {
      const double a = k * M_PI / 4.0;
      const RayHit n = hitAt(px + radius * scale * Vec2(std::cos(a), std::sin(a)));
      if (!n.valid()) continue;  // off the image or undistortion failed: no evidence either way
      const double rel = std::abs(n.distance - c.centre.distance) / std::min(n.distance, c.centre.distance);
      c.max_relative_depth_step = std::max(c.max_relative_depth_step, rel);
      if (rel > options.max_relative_depth_step) step = true;
      if (n.surface != c.centre.surface) {
        if (n.onGate() || c.centre.onGate()) occlusion = true;  // a gate never touches a wall
        else crease = true;
      } else if (n.onGate() && rel > options.max_relative_depth_step) {
        occlusion = true;  // the same gate's front and inner side: its edge over itself
      }
    }
  }
  c.kind = occlusion ? CornerKind::kOcclusion
           : step    ? CornerKind::kSlanted
           : crease  ? CornerKind::kCrease
                     : CornerKind::kSurface;
  return c;
}

}  // namespace hdvio
