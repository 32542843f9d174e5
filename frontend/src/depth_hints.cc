#include "hdvio/frontend/depth_hints.h"

#include <algorithm>

namespace hdvio::frontend {

std::vector<double> hintedDepths(const CameraModel& camera, const Pose& T_cw,
                                 const std::vector<Vec2>& corners_px,
                                 const std::vector<Vec3>& points_W, double radius_px,
                                 double fallback, double min_depth) {
  std::vector<Vec2> px;
  std::vector<double> range;
  for (const Vec3& p_W : points_W) {
    const Vec3 p_c = T_cw * p_W;
    Vec2 uv;
    if (!camera.project(p_c, &uv) || !camera.inImage(uv)) continue;
    px.push_back(uv);
    range.push_back(p_c.norm());
  }
  double median = fallback;
  if (!range.empty()) {
    std::vector<double> sorted = range;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    median = sorted[sorted.size() / 2];
  }
  std::vector<double> depths;
  depths.reserve(corners_px.size());
  const double r2 = radius_px * radius_px;
  for (const Vec2& c : corners_px) {
    double best = r2, depth = median;
    for (std::size_t i = 0; i < px.size(); ++i) {
      const double d2 = (px[i] - c).squaredNorm();
      if (d2 < best) {  // strict: the first of equally near points, in the given order
        best = d2;
        depth = range[i];
      }
    }
    depths.push_back(std::max(depth, min_depth));
  }
  return depths;
}

}  // namespace hdvio::frontend
