#pragma once
// Depth filters (Vogiatzis & Hernandez 2011, as used by SVO): each new feature of a keyframe is
// a seed whose inverse depth follows a Gaussian x Uniform mixture (inlier ratio ~ Beta(a, b)).
// Every tracked frame searches the feature along its epipolar segment, triangulates a depth
// measurement and updates the seed; a seed whose uncertainty has shrunk enough becomes a
// landmark.
#include <vector>

#include "hdvio/core/camera_model.h"
#include "hdvio/frontend/frame.h"

namespace hdvio::frontend {

struct DepthFilterOptions {
  double pixel_noise = 1.0;            // std of the matched pixel, for the measurement variance
  double convergence_ratio = 200.0;    // converged when sigma < z_range / ratio (SVO)
  // ... or, after min_updates_relative measurements, when sigma < relative_sigma * mu (an
  // inverse-depth std of 2 % of the estimate): far seeds converge as soon as they are precise.
  double relative_sigma = 0.02;
  int min_updates_relative = 3;
  double max_zmssd_per_pixel = 2000.0; // worst accepted epipolar match (SVO's threshold)
  int max_search_steps = 200;          // longer epipolar segments are skipped this frame
  double min_parallax_ratio = 0.002;   // skip updates while baseline < ratio * depth
  int max_keyframe_age = 6;            // seeds die after this many newer keyframes
  int max_pyramid_level = 3;
};

struct Seed {
  int id = 0;
  FramePtr keyframe;       // frame the feature was detected in (pose fixed)
  Feature feature;         // in the keyframe
  double mu = 0.0;         // mean inverse depth
  double sigma2 = 0.0;     // variance of the inverse depth
  double a = 10.0, b = 10.0;  // Beta parameters: inlier / outlier evidence
  double z_range = 0.0;    // inverse of the smallest plausible depth
  int keyframe_age = 0;
  int updates = 0;
  double measured_depth = 0.0;  // depth triangulated by the last match (0: none yet)
  int landmark_id = -1;    // provisional landmark that follows this seed (initialization)
  int track_id = -1;       // landmark id its matches are reported under before it converges

  double depth() const { return 1.0 / mu; }
  bool converged(double ratio) const { return std::sqrt(sigma2) < z_range / ratio; }
};

// One Bayesian update with inverse-depth measurement x of variance tau2.
void updateSeed(double x, double tau2, Seed* seed);
// Depth uncertainty from a one-pixel angular error (px_error_angle) for depth z along f_ref,
// given the pose of the current frame in the reference frame.
double computeTau(const Pose& T_ref_cur, const Vec3& f_ref, double z, double px_error_angle);

class DepthFilter {
 public:
  DepthFilter(const CameraModel& camera, DepthFilterOptions options)
      : camera_(camera), options_(options) {}

  // Seeds for the features of a new keyframe, initialized around depth_mean, no closer than
  // depth_min. Returns the new seed ids. Ages the existing seeds by one keyframe.
  std::vector<int> addKeyframe(const FramePtr& keyframe, const std::vector<Feature>& features,
                               double depth_mean, double depth_min);
  // Updates every seed with a frame of known pose; returns (and removes) converged seeds.
  // matches (optional): every seed with a track id matched in this frame, converged or not.
  struct Match {
    int track_id = -1;
    Vec2 px;   // level-0 pixel
    int level = 0;
    int updates = 0;  // the seed's depth updates before this one
  };
  std::vector<Seed> update(const Frame& frame, std::vector<Match>* matches = nullptr);
  void attachLandmark(int seed_id, int landmark_id);
  void setTrackId(int seed_id, int track_id);
  // Drops the seeds of a keyframe that left the map (their patches cannot become landmarks).
  void removeSeedsOf(const FramePtr& keyframe);
  void clear() { seeds_.clear(); }
  const std::vector<Seed>& seeds() const { return seeds_; }

 private:
  // Searches seed's feature along the epipolar segment in frame; *px_found in level-0 pixels.
  bool findEpipolarMatch(const Seed& seed, const Frame& frame, const Pose& T_cur_ref,
                         Vec2* px_found, int* level_found) const;

  CameraModel camera_;
  DepthFilterOptions options_;
  std::vector<Seed> seeds_;
  int next_seed_id_ = 0;
};

}  // namespace hdvio::frontend
