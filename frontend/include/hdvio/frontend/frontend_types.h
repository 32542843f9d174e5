#pragma once
// What goes into and comes out of SemiDirectFrontend::track.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "hdvio/core/lie.h"
#include "hdvio/core/time.h"
#include "hdvio/frontend/depth_filter.h"
#include "hdvio/frontend/feature_detector.h"
#include "hdvio/frontend/pose_optimizer.h"
#include "hdvio/frontend/sparse_image_alignment.h"

namespace hdvio::frontend {

struct ImageFrame {
  Timestamp t = 0;
  cv::Mat image;  // 8-bit grayscale, raw (distorted) camera image
};

// What the rest of the system knows about this image before it is tracked.
struct TrackingPrior {
  // Body rotation from the previously tracked image to this one, R_{B_prev B_cur}
  // (gyroscope integration).
  std::optional<Quat> q_prev_cur;
  // Body pose for this image from the backend (or, in demos, ground truth while the frontend
  // asks for it, see SemiDirectFrontend::wantsPosePrior).
  std::optional<Pose> T_WB;
};

enum class TrackingStage {
  kInitializing,   // no map yet: the next image becomes the first keyframe
  kBootstrapping,  // landmark depths still come from unconverged seeds
  kTracking,
  kRelocalizing,   // tracking was lost; aligning against the last keyframe
};
std::string toString(TrackingStage stage);

// Sent to the backend whenever a keyframe is created.
struct KeyframeBundle {
  struct Observation {
    int landmark_id = 0;
    Vec2 px;      // distorted level-0 pixel
    Vec3 bearing; // unit vector, camera frame (undistorted)
    int level = 0;
  };
  struct NewLandmark {
    int id = 0;
    Vec3 p_W;
    bool converged = true;  // false: depth is still a seed's prior guess (initialization)
    int keyframe_id = 0;    // keyframe of the first observation (may precede this bundle)
    Vec2 px;
    Vec3 bearing;
  };
  int keyframe_id = 0;
  Timestamp t = 0;
  Pose T_WB;  // frontend's estimate
  std::vector<Observation> observations;
  std::vector<NewLandmark> new_landmarks;
};

// Optimized states coming back from the backend.
struct BackendEstimate {
  std::map<int, Pose> keyframe_T_WB;   // by keyframe id
  std::map<int, Vec3> landmark_p_W;    // by landmark id
};

struct FrameTiming {
  double pyramid_ms = 0, alignment_ms = 0, reprojection_ms = 0, optimization_ms = 0,
         depth_filter_ms = 0, keyframe_ms = 0, total_ms = 0;
  double cpu_ms = 0;  // CPU time of the calling thread for the whole image (robust to load)
};

struct FrameResult {
  Timestamp t = 0;
  int frame_id = 0;
  TrackingStage stage = TrackingStage::kInitializing;  // stage after this image
  bool tracked = false;        // a pose was estimated from this image
  bool reinitialized = false;  // the map was discarded and rebuilt on this image
  Pose T_WB;                   // when not tracked: the last tracked pose
  int tracked_features = 0;    // landmarks matched and kept as inliers in this image
  int landmarks = 0;           // in the map
  int seeds = 0;               // depth filters alive
  double alignment_rms = 0.0;  // photometric RMS of sparse alignment
  double reprojection_rms_px = 0.0;
  // Landmarks measured in this image (pose-refinement inliers, or the features of a new first
  // keyframe): what a backend turns into reprojection factors. Empty when not tracked.
  std::vector<KeyframeBundle::Observation> observations;
  std::optional<KeyframeBundle> keyframe;
  FrameTiming timing;
};

struct FrontendOptions {
  int pyramid_levels = 5;
  int max_features = 180;            // matched landmarks per image at most
  int min_tracked_features = 30;     // fewer inliers: tracking is lost
  int keyframe_min_tracked = 70;     // fewer tracked landmarks: take a keyframe
  double keyframe_distance = 0.12;   // SVO: distance to every keyframe / median depth
  int max_keyframes = 10;
  double init_depth = 3.0;           // m, seed prior of the first keyframe (no depth known yet)
  double init_min_depth = 0.5;       // m
  int bootstrap_max_frames = 10;     // frames that may use pose priors before trusting the map
  int bootstrap_min_converged = 50;  // converged landmarks that end bootstrapping early
  int max_relocalization_frames = 5; // then re-initialize; 0: re-initialize on the image lost
  bool constant_velocity = true;     // predict the translation from the last two frames
  int structure_points_per_frame = 20;
  int landmark_max_failures = 15;
  DetectorOptions detector;
  SparseAlignmentOptions alignment;
  PoseOptimizerOptions pose;
  DepthFilterOptions depth_filter;
};

}  // namespace hdvio::frontend
