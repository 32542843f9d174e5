#pragma once
// SVO-like semi-direct visual frontend (Forster et al., T-RO 2017):
//   sparse image alignment against the previous frame (IMU rotation as prior)
//   -> feature alignment of map landmarks against their keyframes
//   -> pose-only and structure-only refinement -> depth filters -> keyframe selection.
// Keyframes are emitted as KeyframeBundles for the backend, whose optimized states come back
// through applyBackendEstimate. One instance tracks one camera, single-threaded.
//
// Initialization: the first image becomes a keyframe whose features are depth-filter seeds
// with a prior depth (FrontendOptions::init_depth). While bootstrapping, the seeds stand in as
// provisional landmarks and the frontend asks for pose priors (wantsPosePrior); with them the
// seeds converge from real parallax, without them (or after bootstrap_max_frames) the map is
// consistent only up to scale until the backend corrects it.
#include <optional>

#include "hdvio/core/sequence.h"
#include "hdvio/core/camera_model.h"
#include "hdvio/frontend/depth_filter.h"
#include "hdvio/frontend/feature_detector.h"
#include "hdvio/frontend/frame.h"
#include "hdvio/frontend/frontend_types.h"

namespace hdvio::frontend {

class SemiDirectFrontend {
 public:
  SemiDirectFrontend(const CameraCalibration& calibration, FrontendOptions options = {});

  // Throws InputError for an empty / non-8-bit image, a wrong image size or a timestamp that
  // does not increase.
  FrameResult track(const ImageFrame& frame, const TrackingPrior& prior = {});

  // True while a backend (or ground-truth) pose for the next image would be used: to start or
  // restart a map and to relocalize. While tracking, a given pose only seeds the alignment.
  bool wantsPosePrior() const { return stage_ != TrackingStage::kTracking; }
  void applyBackendEstimate(const BackendEstimate& estimate);
  void reset();

  TrackingStage stage() const { return stage_; }
  const Map& map() const { return map_; }
  const DepthFilter& depthFilter() const { return depth_filter_; }
  const CameraModel& camera() const { return camera_; }

 private:
  bool initialize(const FramePtr& frame, const TrackingPrior& prior, FrameResult* result);
  // Aligns frame against ref (unless the pose is fixed), matches landmarks and refines.
  bool trackAgainst(const FramePtr& frame, const Frame& ref, const Pose& T_cur_ref_guess,
                    const std::optional<Quat>& rotation_prior, bool pose_fixed,
                    FrameResult* result);
  void refineStructure(const Frame& frame);
  void updateDepthFilter(const Frame& frame);
  void addKeyframe(const FramePtr& frame, FrameResult* result);
  int convergedLandmarks() const;
  // The seeds matched in this image (seed_matches_) as observations of their tracks, so the
  // backend sees a new feature from its keyframe on, not from its convergence.
  void appendSeedTracks(const Frame& frame, std::vector<KeyframeBundle::Observation>* observations) const;

  Pose cameraToBody(const Pose& T_cw) const { return T_cw.inverse() * T_BS_.inverse(); }
  Pose bodyToCamera(const Pose& T_WB) const { return (T_WB * T_BS_).inverse(); }

  CameraModel camera_;
  Pose T_BS_;
  FrontendOptions options_;
  FeatureGrid grid_;
  Map map_;
  DepthFilter depth_filter_;

  TrackingStage stage_ = TrackingStage::kInitializing;
  FramePtr last_frame_;                    // last successfully tracked frame
  std::optional<Pose> last_T_cw_;          // its pose; survives reset() for re-initialization
  std::optional<Vec3> velocity_w_;         // camera center velocity between the last two frames
  Quat q_since_last_ = Quat::Identity();   // body rotation from last_frame_ to the current image
  bool have_rotation_prior_ = false;
  Timestamp last_t_ = 0;
  bool any_frame_ = false;
  int next_frame_id_ = 0;
  int bootstrap_frames_ = 0;
  // The run's first map (the start, usually at rest: first matches at little parallax, their
  // depths noisy) places its provisional landmarks at the seeds' mixture mean; a later map
  // (made in flight) at their first match's depth, then at the mean.
  bool first_map_ = true;
  int relocalization_frames_ = 0;
  int frames_since_keyframe_ = 0;
  int structure_cursor_ = 0;
  std::vector<KeyframeBundle::NewLandmark> pending_landmarks_;  // for the next bundle
  std::vector<DepthFilter::Match> seed_matches_;  // this image's seeds: new ones and matches
};

}  // namespace hdvio::frontend
