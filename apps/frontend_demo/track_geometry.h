#pragma once
// Checks the visual pipeline's frontend observations against a flight's true camera poses when
// the scene is unknown (flights of another simulator, or real flights with precise ground truth).
// Each landmark's point is triangulated from all its observations at the true camera poses; every
// observation's reprojection error at its true pose is what the backend sees of that track
// (patch drift, noise, mismatches), independent of the estimated poses. Tracks seen in fewer than
// three images or with less than `min_parallax_deg` between their rays are not scored (their
// point is not determined by the poses).
#include <map>
#include <string>
#include <vector>

#include "feature_truth.h"
#include "hdvio/core/camera_model.h"
#include "hdvio/pipeline/visual_sequence_runner.h"

namespace hdvio {

class TrackGeometryChecker {
 public:
  using TruthPose = FeatureTruthChecker::TruthPose;
  TrackGeometryChecker(CameraModel camera, const Pose& T_BS, TruthPose truth, double min_parallax_deg = 1.0);

  void add(const ImageStep& step);
  // by_corner / by_span / new-landmark depth errors stay empty (they need the scene).
  FeatureTruthSummary summary() const;
  int landmarksInThreeImages() const;  // the tracks long enough to be scored

 private:
  struct Obs {
    Timestamp t;
    int image, level;
    Vec2 px;
  };
  CameraModel camera_;
  Pose T_BS_;
  TruthPose truth_;
  double min_parallax_rad_;
  std::map<int, std::vector<Obs>> tracks_;
  PipelineCounts counts_;
};

std::string formatGeometrySummary(const FeatureTruthSummary& s, const ImageRunOutput& run, int scored);

}  // namespace hdvio
