#include "track_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "hdvio/backend/triangulation.h"

namespace hdvio {

TrackGeometryChecker::TrackGeometryChecker(CameraModel camera, const Pose& T_BS, TruthPose truth,
                                           double min_parallax_deg)
    : camera_(std::move(camera)), T_BS_(T_BS), truth_(std::move(truth)),
      min_parallax_rad_(min_parallax_deg * M_PI / 180.0) {}

void TrackGeometryChecker::add(const ImageStep& step) {
  const int image = images_++;
  if (!step.record.tracked) return;
  ++tracked_;
  keyframes_ += step.record.frontend_keyframe;
  observations_ += static_cast<long long>(step.observations.size());
  for (const auto& o : step.observations)
    tracks_[o.landmark_id].push_back({step.record.t, image, o.level, o.px});
  if (step.result && step.record.used_by_backend) {
    ++backend_frames_;
    backend_obs_ += step.result->observations_used;
    backend_landmarks_ += step.result->landmarks_in_window;
    backend_outliers_ += step.result->outliers_removed;
  }
}

FeatureTruthSummary TrackGeometryChecker::summary() const {
  FeatureTruthSummary s;
  s.images = images_;
  s.tracked_images = tracked_;
  s.backend_images = backend_frames_;
  s.keyframes = keyframes_;
  s.observations_per_image = tracked_ ? static_cast<double>(observations_) / tracked_ : 0.0;
  const std::vector<std::pair<std::string, int>> ages = {
      {"1-2", 2}, {"3-5", 5}, {"6-10", 10}, {"11-20", 20}, {"21-40", 40}, {">40", 1 << 30}};
  std::vector<double> all, lengths;
  std::map<int, std::vector<double>> level;
  std::vector<std::vector<double>> age(ages.size());
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
      if (!camera_.project(T_WC[k].inverse() * tri.p_W, &uv)) continue;
      const double e = (obs[k].px - uv).norm();
      all.push_back(e);
      level[obs[k].level].push_back(e);
      const int a = obs[k].image - obs.front().image;
      for (size_t j = 0; j < ages.size(); ++j)
        if (a <= ages[j].second) {
          age[j].push_back(e);
          break;
        }
    }
  }
  s.all = errorStats(all);
  for (auto& [l, v] : level) s.by_level[l] = errorStats(v);
  for (size_t j = 0; j < ages.size(); ++j) s.by_age.push_back({ages[j].first, errorStats(age[j])});
  s.landmarks = static_cast<int>(lengths.size());
  if (!lengths.empty()) {
    double sum = 0;
    for (double l : lengths) sum += l;
    s.track_mean = sum / static_cast<double>(lengths.size());
  }
  s.track_median = quantile(lengths, 0.5);
  s.track_p90 = quantile(lengths, 0.9);
  if (backend_frames_ > 0) {
    s.backend_observations = backend_obs_ / backend_frames_;
    s.backend_landmarks = backend_landmarks_ / backend_frames_;
    s.backend_outliers_per_image = backend_outliers_ / backend_frames_;
  }
  return s;
}

int TrackGeometryChecker::scoredLandmarks() const {
  int n = 0;
  for (const auto& [id, obs] : tracks_) n += obs.size() >= 3;
  return n;
}

std::string formatGeometrySummary(const FeatureTruthSummary& s, const ImageRunOutput& run, int scored) {
  std::string o;
  char b[512];
  std::snprintf(b, sizeof(b), "images %d, tracked %d, given to the backend %d, lost %d, re-initializations %d, "
                "frontend keyframes %d\n", s.images, s.tracked_images, s.backend_images,
                run.lost_images, run.reinitializations, s.keyframes);
  o += b;
  std::snprintf(b, sizeof(b), "frontend observations per tracked image %.1f; landmarks %d (%d seen in >= 3 "
                "images), images per track mean %.1f median %.0f p90 %.0f\n", s.observations_per_image,
                s.landmarks, scored, s.track_mean, s.track_median, s.track_p90);
  o += b;
  o += "reprojection error at the true poses of the track's point triangulated from them [px], all: " +
       statsLine(s.all) + "\n";
  for (const auto& [l, st] : s.by_level) o += "  level " + std::to_string(l) + ":  " + statsLine(st) + "\n";
  for (const auto& [a, st] : s.by_age) {
    std::snprintf(b, sizeof(b), "  age %-6s ", a.c_str());
    o += b + statsLine(st) + "\n";
  }
  std::snprintf(b, sizeof(b), "backend per image: observations used %.1f, landmarks in window %.1f, "
                "outliers removed %.2f\n", s.backend_observations, s.backend_landmarks,
                s.backend_outliers_per_image);
  o += b;
  return o;
}

}  // namespace hdvio
