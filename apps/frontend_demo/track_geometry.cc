#include "track_geometry.h"

#include <cmath>

#include "hdvio/backend/triangulation.h"

namespace hdvio {

TrackGeometryChecker::TrackGeometryChecker(CameraModel camera, const Pose& T_BS, TruthPose truth,
                                           double min_parallax_deg)
    : camera_(std::move(camera)), T_BS_(T_BS), truth_(std::move(truth)),
      min_parallax_rad_(min_parallax_deg * M_PI / 180.0) {}

void TrackGeometryChecker::add(const ImageStep& step) {
  const int image = counts_.images();
  counts_.add(step);
  if (!step.record.tracked) return;
  for (const auto& o : step.observations)
    tracks_[o.landmark_id].push_back({step.record.t, image, o.level, o.px});
}

FeatureTruthSummary TrackGeometryChecker::summary() const {
  FeatureTruthSummary s;
  counts_.fill(&s);
  std::vector<ScoredObservation> scored;
  std::vector<double> lengths;
  for (const auto& [id, obs] : tracks_) {
    lengths.push_back(static_cast<double>(obs.size()));
    if (obs.size() < 3) continue;
    std::vector<Pose> T_WC;
    std::vector<Vec3> rays;
    for (const Obs& o : obs) {
      T_WC.push_back(truth_(o.t) * T_BS_);
      rays.push_back(camera_.unproject(o.px).normalized());
    }
    const TriangulationResult tri = triangulate(T_WC, rays);
    if (!tri.valid || tri.max_ray_angle_rad < min_parallax_rad_) continue;
    for (size_t k = 0; k < obs.size(); ++k) {
      Vec2 uv;
      if (camera_.project(T_WC[k].inverse() * tri.p_W, &uv))
        scored.push_back({(obs[k].px - uv).norm(), obs[k].level, obs[k].image - obs.front().image});
    }
  }
  fillErrorBreakdown(scored, lengths, &s);
  return s;
}

int TrackGeometryChecker::landmarksInThreeImages() const {
  int n = 0;
  for (const auto& [id, obs] : tracks_) n += obs.size() >= 3;
  return n;
}

std::string formatGeometrySummary(const FeatureTruthSummary& s, const ImageRunOutput& run, int scored) {
  return formatErrorSummary(s, run, "reprojection error at the true poses of the track's point triangulated from them",
                            scored) +
         formatBackendLine(s);
}

}  // namespace hdvio
