#include "hdvio/frontend/reprojector.h"

#include <algorithm>

#include "hdvio/frontend/patch_alignment.h"

namespace hdvio::frontend {
namespace {

struct Candidate {
  Landmark* landmark;
  Vec2 px;
  bool converged;
};

// The observation whose viewing direction is closest to the current one (SVO: close view).
const Landmark::Observation* closestView(const Landmark& lm, const Vec3& center_cur) {
  const Vec3 dir_cur = (center_cur - lm.p_w).normalized();
  const Landmark::Observation* best = nullptr;
  double best_cos = -2.0;
  for (const auto& o : lm.observations) {
    const double c = (o.keyframe->cameraCenter() - lm.p_w).normalized().dot(dir_cur);
    if (c > best_cos) {
      best_cos = c;
      best = &o;
    }
  }
  return best_cos > 0.5 ? best : nullptr;  // beyond 60 degrees the patch looks too different
}

bool alignToFrame(const CameraModel& camera, const Landmark& lm, const Landmark::Observation& obs,
                  Frame* frame, Vec2* px, int* level_out) {
  const Frame& kf = *obs.keyframe;
  const Feature& ref = kf.features[obs.feature];
  const Pose T_cur_ref = frame->T_cw * kf.T_cw.inverse();
  const double depth_ref = (kf.T_cw * lm.p_w).norm();
  const Eigen::Matrix2d A = affineWarp(camera, ref.px, ref.f, depth_ref, ref.level, T_cur_ref);
  const int max_level = static_cast<int>(frame->pyramid.size()) - 1;
  const int level = std::max(bestSearchLevel(A, max_level),
                             lm.converged ? 0 : std::min(kUnconvergedLevel, max_level));
  BorderedPatch patch;
  if (!warpPatchFromPyramid(A, kf.pyramid, ref.px, ref.level, level, &patch)) return false;
  Vec2 p = *px / static_cast<double>(1 << level);
  if (!align2D(frame->pyramid[level], patch, 10, &p)) return false;
  const int finest = refineToFinerLevels(frame->pyramid, A, kf.pyramid, ref.px, ref.level, level, &p);
  *px = p * static_cast<double>(1 << finest);
  *level_out = finest;
  return true;
}

}  // namespace

ReprojectionStats reprojectMap(const CameraModel& camera, const FeatureGrid& grid, int max_features,
                               int landmark_max_failures, Map* map, Frame* frame) {
  ReprojectionStats stats;
  std::vector<std::vector<Candidate>> cells(grid.cells());
  for (auto& [id, lm] : map->landmarks) {
    Vec2 px;
    if (!camera.project(frame->T_cw * lm->p_w, &px) || !camera.inImage(px, 8.0)) continue;
    const int cell = grid.cellIndex(px);
    if (cell < 0) continue;
    cells[cell].push_back({lm.get(), px, lm->converged});
    ++stats.candidates;
  }
  const Vec3 center = frame->cameraCenter();
  std::vector<int> to_remove;
  for (auto& cell : cells) {
    if (stats.matched >= max_features) break;
    std::stable_sort(cell.begin(), cell.end(), [](const Candidate& a, const Candidate& b) {
      return a.converged > b.converged ||
             (a.converged == b.converged && a.landmark->failed_alignments < b.landmark->failed_alignments);
    });
    for (const Candidate& c : cell) {
      const Landmark::Observation* obs = closestView(*c.landmark, center);
      if (!obs) continue;
      Vec2 px = c.px;
      int level = 0;
      if (!alignToFrame(camera, *c.landmark, *obs, frame, &px, &level)) {
        ++stats.failed;
        if (++c.landmark->failed_alignments > landmark_max_failures)
          to_remove.push_back(c.landmark->id);
        continue;
      }
      Feature ftr;
      ftr.px = px;
      ftr.f = camera.unproject(px);
      ftr.level = level;
      ftr.landmark_id = c.landmark->id;
      frame->features.push_back(ftr);
      c.landmark->failed_alignments = std::max(0, c.landmark->failed_alignments - 1);
      ++stats.matched;
      break;  // one feature per cell
    }
  }
  for (int id : to_remove) map->removeLandmark(id);
  return stats;
}

}  // namespace hdvio::frontend
