#pragma once
// Checks the visual pipeline's frontend observations against a simulated scene
// (hdvio_feature_truth). A landmark's true point is where the ray of its first observation, cast
// from the true camera pose, meets the scene; each later observation is compared with the
// projection of that point at the true pose of its image. So the error is what the backend sees:
// how far a track moves off the physical point it started on (patch drift, noise, mismatches),
// independent of the estimated poses.
#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "hdvio/core/camera_model.h"
#include "hdvio/pipeline/visual_sequence_runner.h"
#include "hdvio/sim/scene.h"
#include "scene_rays.h"

namespace hdvio {

struct ErrorStats {
  int count = 0;
  double rms = 0, median = 0, p90 = 0;
  double frac_above_1px = 0, frac_above_2px = 0, frac_above_5px = 0;
  double rms_below_5px = 0;  // the noise part, mismatches left out
};
// The q-quantile by nearest rank; 0 for an empty vector.
double quantile(std::vector<double> v, double q);
ErrorStats errorStats(std::vector<double> errors_px);
// One line: count, rms, median, p90, fractions above 1 / 2 / 5 px, rms below 5 px.
std::string statsLine(const ErrorStats& s);

struct FeatureTruthSummary {
  int images = 0, tracked_images = 0, backend_images = 0, keyframes = 0;
  double observations_per_image = 0;        // frontend observations, tracked images
  ErrorStats all;                           // observations after the first of each landmark
  std::map<int, ErrorStats> by_level;       // pyramid level of the observation
  std::vector<std::pair<std::string, ErrorStats>> by_age;  // images since the first observation
  // By the class of the landmark's first observation (scene_rays.h): all flight, and per span
  // of flight time (first image = 0 s).
  std::array<ErrorStats, kNumCornerKinds> by_corner;
  std::array<int, kNumCornerKinds> landmarks_by_corner{};
  struct SpanRow {
    std::string span;
    std::array<ErrorStats, kNumCornerKinds> by_corner;
  };
  std::vector<SpanRow> by_span;
  int landmarks = 0;                        // distinct landmark ids observed
  double track_mean = 0, track_median = 0, track_p90 = 0;  // images per landmark
  double new_landmarks_per_keyframe = 0, new_unconverged_fraction = 0;
  double new_depth_error_median = 0, new_depth_error_p90 = 0;  // |d - d_true| / d_true
  // Backend, over images it processed with observations.
  double backend_observations = 0, backend_landmarks = 0, backend_outliers_per_image = 0;
};

// What both checkers count of the pipeline, whatever their truth: images, tracked images,
// frontend keyframes, observations, and the backend's observations, landmarks and outliers.
class PipelineCounts {
 public:
  void add(const ImageStep& step);
  int images() const { return images_; }
  void fill(FeatureTruthSummary* s) const;

 private:
  int images_ = 0, tracked_ = 0, keyframes_ = 0, backend_frames_ = 0;
  long long observations_ = 0;
  double backend_obs_ = 0, backend_landmarks_ = 0, backend_outliers_ = 0;
};

// A scored observation: its error [px], pyramid level and age (images since the track's first).
struct ScoredObservation {
  double error_px;
  int level, age;
};
// s->all, by_level and by_age of the observations; landmarks and track lengths from the number
// of images of each track.
void fillErrorBreakdown(const std::vector<ScoredObservation>& scored, const std::vector<double>& track_lengths,
                        FeatureTruthSummary* s);

class FeatureTruthChecker {
 public:
  using TruthPose = std::function<Pose(Timestamp)>;  // true T_WB at an image time
  FeatureTruthChecker(const sim::Scene& scene, CameraModel camera, const Pose& T_BS, TruthPose truth,
                      CornerClassOptions corner_options = {});

  void add(const ImageStep& step);
  FeatureTruthSummary summary() const;
  // Every checked observation: t [ns], landmark, level, age [images], error u, v [px], observed
  // u, v [px], and its landmark's first observation: class, surface, distance [m], level, u, v.
  void writeObservations(const std::string& path) const;

 private:
  struct Track {
    bool valid = false;  // the first ray met the scene
    Vec3 p_W = Vec3::Zero();
    int first_image = 0, count = 0, first_level = 0;
    Vec2 first_px = Vec2::Zero();
    CornerClass corner;
  };
  struct Checked {
    Timestamp t;
    int id, level, age;
    Vec2 err, px;
  };
  Pose trueCamera(Timestamp t) const { return truth_(t) * T_BS_; }

  const sim::Scene& scene_;
  CameraModel camera_;
  Pose T_BS_;
  TruthPose truth_;
  CornerClassOptions corner_options_;
  Timestamp first_t_ = 0;
  std::map<int, Track> tracks_;
  std::vector<Checked> checked_;
  std::vector<double> new_depth_errors_;
  PipelineCounts counts_;
  int new_landmarks_ = 0, new_unconverged_ = 0;
};

std::string formatSummary(const FeatureTruthSummary& s, const ImageRunOutput& run);
// The lines every summary prints: counts, track lengths (with the number of landmarks seen in
// 3+ images when >= 0), the error of all observations (titled `what`), by level and by age.
std::string formatErrorSummary(const FeatureTruthSummary& s, const ImageRunOutput& run,
                               const std::string& what, int scored_landmarks);
std::string formatBackendLine(const FeatureTruthSummary& s);

}  // namespace hdvio
