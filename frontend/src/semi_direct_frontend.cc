#include "hdvio/frontend/semi_direct_frontend.h"

#include <algorithm>
#include <chrono>
#include <set>

#include "hdvio/core/error.h"
#include "hdvio/core/thread_clock.h"
#include "hdvio/frontend/keyframe_selection.h"
#include "hdvio/frontend/pose_optimizer.h"
#include "hdvio/frontend/reprojector.h"

namespace hdvio::frontend {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

std::string toString(TrackingStage stage) {
  switch (stage) {
    case TrackingStage::kInitializing: return "initializing";
    case TrackingStage::kBootstrapping: return "bootstrapping";
    case TrackingStage::kTracking: return "tracking";
    case TrackingStage::kRelocalizing: return "relocalizing";
  }
  return "unknown";
}

SemiDirectFrontend::SemiDirectFrontend(const CameraCalibration& calibration,
                                       FrontendOptions options)
    : camera_(CameraModel::fromCalibration(calibration)),
      T_BS_(calibration.T_BS),
      options_(options),
      grid_(camera_.width(), camera_.height(), options.detector.cell_size),
      depth_filter_(camera_, options.depth_filter) {
  // Small images get fewer levels: the coarsest one keeps at least 16 pixels per side.
  int levels = 1;
  while (levels < options_.pyramid_levels &&
         (std::min(camera_.width(), camera_.height()) >> levels) >= 16)
    ++levels;
  options_.pyramid_levels = levels;
}

void SemiDirectFrontend::reset() {
  map_.clear();
  depth_filter_.clear();
  pending_landmarks_.clear();
  stage_ = TrackingStage::kInitializing;
  last_frame_.reset();
  velocity_w_.reset();
  q_since_last_ = Quat::Identity();
  have_rotation_prior_ = false;
}

FrameResult SemiDirectFrontend::track(const ImageFrame& input, const TrackingPrior& prior) {
  const auto t_start = Clock::now();
  const double cpu_start = threadCpuSeconds();
  if (input.image.empty() || input.image.type() != CV_8UC1)
    throw InputError("", 0, "frontend: image at t=" + std::to_string(input.t) +
                                " is not a non-empty 8-bit grayscale image");
  if (input.image.cols != camera_.width() || input.image.rows != camera_.height())
    throw InputError("", 0, "frontend: image at t=" + std::to_string(input.t) + " is " +
                                std::to_string(input.image.cols) + "x" +
                                std::to_string(input.image.rows) + ", calibration says " +
                                std::to_string(camera_.width()) + "x" +
                                std::to_string(camera_.height()));
  if (any_frame_ && input.t <= last_t_)
    throw InputError("", 0, "frontend: image timestamps must increase (" +
                                std::to_string(input.t) + " after " + std::to_string(last_t_) + ")");
  any_frame_ = true;
  last_t_ = input.t;

  FrameResult result;
  result.t = input.t;
  seed_matches_.clear();
  auto frame = std::make_shared<Frame>();
  frame->id = next_frame_id_++;
  frame->t = input.t;
  result.frame_id = frame->id;
  auto t0 = Clock::now();
  frame->pyramid = buildPyramid(input.image, options_.pyramid_levels);
  result.timing.pyramid_ms = msSince(t0);

  if (prior.q_prev_cur) {
    q_since_last_ = (q_since_last_ * *prior.q_prev_cur).normalized();
    have_rotation_prior_ = true;
  }

  bool tracked = false;
  if (stage_ == TrackingStage::kInitializing) {
    tracked = initialize(frame, prior, &result);
  } else {
    // Prediction: last pose rotated by the gyroscope, or the backend's pose when given.
    const Quat R_bc = T_BS_.q;
    const Quat q_cur_last = (R_bc.conjugate() * q_since_last_ * R_bc).conjugate();
    std::optional<Quat> rotation_prior;
    if (have_rotation_prior_) rotation_prior = q_cur_last;
    Pose T_cur_last_guess(q_cur_last, Vec3::Zero());
    if (options_.constant_velocity && velocity_w_) {
      // Camera center moved on at the last measured velocity, expressed in the last camera.
      const Vec3 d = last_frame_->T_cw.q * (*velocity_w_ * secondsBetween(last_frame_->t, frame->t));
      T_cur_last_guess.p = -(q_cur_last * d);
    }
    if (prior.T_WB) T_cur_last_guess = bodyToCamera(*prior.T_WB) * last_frame_->T_cw.inverse();

    const bool pose_fixed = stage_ == TrackingStage::kBootstrapping && prior.T_WB.has_value();
    bool depth_filter_done = false;
    if (pose_fixed) {
      // A map bootstrapping on the backend's poses: its provisional landmarks still sit at the
      // depths of the last image (init_depth at first), which at speed puts them pixels off.
      // The seeds are searched along their epipolar lines on the given pose first, and the
      // landmarks that follow them are matched where the seeds found them.
      frame->T_cw = T_cur_last_guess * last_frame_->T_cw;
      t0 = Clock::now();
      updateDepthFilter(*frame);
      result.timing.depth_filter_ms = msSince(t0);
      depth_filter_done = true;
    }
    tracked = trackAgainst(frame, *last_frame_, T_cur_last_guess, rotation_prior, pose_fixed,
                           &result);
    if (pose_fixed) tracked = true;  // a backend pose is a pose even when few landmarks matched
    if (stage_ == TrackingStage::kBootstrapping) {
      ++bootstrap_frames_;
      if (!tracked) {
        // The provisional map did not hold: start again from this image.
        reset();
        frame->features.clear();
        tracked = initialize(frame, prior, &result);
        result.reinitialized = tracked;
      } else if (bootstrap_frames_ >= options_.bootstrap_max_frames ||
                 convergedLandmarks() >= options_.bootstrap_min_converged) {
        stage_ = TrackingStage::kTracking;
      }
    } else if (!tracked) {
      if (options_.max_relocalization_frames == 0) {
        // No relocalization: a new map on this image (at the backend's pose when given), so
        // the image is not lost.
        reset();
        frame->features.clear();
        tracked = initialize(frame, prior, &result);
        result.reinitialized = tracked;
      } else if (stage_ == TrackingStage::kTracking) {
        stage_ = TrackingStage::kRelocalizing;
        relocalization_frames_ = 0;
      } else if (++relocalization_frames_ >= options_.max_relocalization_frames) {
        reset();
        frame->features.clear();
        tracked = initialize(frame, prior, &result);
        result.reinitialized = tracked;
      }
    } else {
      stage_ = TrackingStage::kTracking;
    }
    if (tracked && !result.reinitialized) {
      if (!depth_filter_done) {
        t0 = Clock::now();
        updateDepthFilter(*frame);
        result.timing.depth_filter_ms = msSince(t0);
      }
      t0 = Clock::now();
      double median_depth = options_.init_depth, min_depth = options_.init_min_depth;
      sceneDepth(*frame, map_, &median_depth, &min_depth);
      KeyframePolicy policy;
      policy.distance = options_.keyframe_distance;
      policy.min_tracked = options_.keyframe_min_tracked;
      if (needNewKeyframe(*frame, map_.keyframes, median_depth, result.tracked_features,
                          ++frames_since_keyframe_, policy))
        addKeyframe(frame, &result);
      result.timing.keyframe_ms = msSince(t0);
    }
  }
  if (tracked) {
    if (last_frame_ && !result.reinitialized && last_frame_->t < frame->t &&
        secondsBetween(last_frame_->t, frame->t) < 0.25)
      velocity_w_ = (frame->cameraCenter() - last_frame_->cameraCenter()) /
                    secondsBetween(last_frame_->t, frame->t);
    else
      velocity_w_.reset();
    last_frame_ = frame;
    last_T_cw_ = frame->T_cw;
    q_since_last_ = Quat::Identity();
    have_rotation_prior_ = false;
  }
  result.tracked = tracked;
  if (tracked) {
    for (const Feature& f : frame->features)
      if (f.landmark_id >= 0) result.observations.push_back({f.landmark_id, f.px, f.f, f.level});
    appendSeedTracks(*frame, &result.observations);
  }
  result.stage = stage_;
  result.T_WB = cameraToBody(tracked || !last_frame_ ? frame->T_cw : last_frame_->T_cw);
  result.landmarks = static_cast<int>(map_.landmarks.size());
  result.seeds = static_cast<int>(depth_filter_.seeds().size());
  result.timing.total_ms = msSince(t_start);
  result.timing.cpu_ms = 1e3 * (threadCpuSeconds() - cpu_start);
  return result;
}

bool SemiDirectFrontend::initialize(const FramePtr& frame, const TrackingPrior& prior,
                                    FrameResult* result) {
  const auto t0 = Clock::now();
  first_map_ = !last_T_cw_.has_value();
  // Without a prior the new map starts where the camera was last seen (the world origin at
  // the very start), so a re-initialization does not make the trajectory jump.
  frame->T_cw = prior.T_WB ? bodyToCamera(*prior.T_WB)
                           : (last_T_cw_ ? *last_T_cw_ : bodyToCamera(Pose()));
  const std::vector<Corner> corners =
      detectCorners(frame->pyramid, options_.detector, grid_, std::vector<bool>(grid_.cells(), false));
  if (static_cast<int>(corners.size()) < options_.min_tracked_features) {
    result->timing.keyframe_ms = msSince(t0);
    return false;
  }
  frame->features.clear();
  for (const Corner& c : corners) frame->features.push_back({c.px, camera_.unproject(c.px), c.level, -1});
  frame->is_keyframe = true;
  map_.keyframes.push_back(frame);
  // Every corner starts at init_depth, never closer than init_min_depth.
  const double depth = std::max(options_.init_depth, options_.init_min_depth);
  const std::vector<int> seed_ids =
      depth_filter_.addKeyframe(frame, frame->features, depth, options_.init_min_depth);
  const Pose T_wc = frame->T_cw.inverse();
  KeyframeBundle bundle;
  for (std::size_t i = 0; i < frame->features.size(); ++i) {
    Feature& ftr = frame->features[i];
    LandmarkPtr lm = map_.addLandmark(T_wc * (ftr.f * depth), /*converged=*/false);
    lm->observations.push_back({frame, static_cast<int>(i)});
    ftr.landmark_id = lm->id;
    depth_filter_.attachLandmark(seed_ids[i], lm->id);
    bundle.observations.push_back({lm->id, ftr.px, ftr.f, ftr.level});
    bundle.new_landmarks.push_back({lm->id, lm->p_w, false, frame->id, ftr.px, ftr.f});
  }
  bundle.keyframe_id = frame->id;
  bundle.t = frame->t;
  bundle.T_WB = cameraToBody(frame->T_cw);
  result->keyframe = std::move(bundle);
  result->tracked_features = static_cast<int>(frame->features.size());
  stage_ = TrackingStage::kBootstrapping;
  bootstrap_frames_ = 0;
  frames_since_keyframe_ = 0;
  result->timing.keyframe_ms = msSince(t0);
  return true;
}

bool SemiDirectFrontend::trackAgainst(const FramePtr& frame, const Frame& ref,
                                      const Pose& T_cur_ref_guess,
                                      const std::optional<Quat>& rotation_prior, bool pose_fixed,
                                      FrameResult* result) {
  auto t0 = Clock::now();
  frame->T_cw = T_cur_ref_guess * ref.T_cw;
  if (!pose_fixed) {
    std::vector<Vec3> points_ref;
    for (const Feature& f : ref.features) {
      auto it = map_.landmarks.find(f.landmark_id);
      if (it != map_.landmarks.end()) points_ref.push_back(ref.T_cw * it->second->p_w);
    }
    const SparseAlignmentResult aligned =
        alignSparse(camera_, ref.pyramid, points_ref, frame->pyramid, T_cur_ref_guess,
                    rotation_prior, options_.alignment);
    result->alignment_rms = aligned.rms_error;
    result->timing.alignment_ms = msSince(t0);
    if (!aligned.ok) return false;
    frame->T_cw = aligned.T_cur_ref * ref.T_cw;
  }

  t0 = Clock::now();
  frame->features.clear();
  reprojectMap(camera_, grid_, options_.max_features, options_.landmark_max_failures, &map_,
               frame.get());
  result->timing.reprojection_ms = msSince(t0);

  t0 = Clock::now();
  std::vector<PoseObservation> obs;
  obs.reserve(frame->features.size());
  for (const Feature& f : frame->features) {
    const Landmark& lm = *map_.landmarks.at(f.landmark_id);
    obs.push_back({lm.p_w, f.f, lm.converged ? f.level : std::max(f.level, kUnconvergedLevel)});
  }
  PoseOptimizerOptions pose_options = options_.pose;
  if (pose_fixed) pose_options.iterations = 0;  // only classify inliers
  const PoseOptimizerResult refined =
      optimizePose(frame->T_cw, obs, camera_.focalLength(), pose_options);
  frame->T_cw = refined.T_cw;
  std::vector<Feature> inliers;
  for (std::size_t i = 0; i < frame->features.size(); ++i)
    if (refined.inlier[i]) inliers.push_back(frame->features[i]);
  frame->features = std::move(inliers);
  result->tracked_features = refined.inliers;
  result->reprojection_rms_px = refined.rms_px;
  if (refined.inliers >= options_.min_tracked_features) refineStructure(*frame);
  result->timing.optimization_ms = msSince(t0);
  return refined.inliers >= options_.min_tracked_features;
}

void SemiDirectFrontend::refineStructure(const Frame& frame) {
  const int n = static_cast<int>(frame.features.size());
  const int count = std::min(n, options_.structure_points_per_frame);
  for (int k = 0; k < count; ++k) {
    const Feature& f = frame.features[(structure_cursor_ + k) % n];
    Landmark& lm = *map_.landmarks.at(f.landmark_id);
    if (!lm.converged || lm.observations.size() < 2) continue;
    std::vector<PointObservation> obs;
    for (const auto& o : lm.observations) obs.push_back({o.keyframe->T_cw, o.keyframe->features[o.feature].f});
    obs.push_back({frame.T_cw, f.f});
    optimizePoint(obs, 5, &lm.p_w);
  }
  structure_cursor_ += count;
}

void SemiDirectFrontend::updateDepthFilter(const Frame& frame) {
  const std::vector<Seed> converged = depth_filter_.update(frame, &seed_matches_);
  // Provisional landmarks follow their seeds.
  for (const Seed& s : depth_filter_.seeds()) {
    if (s.landmark_id < 0) continue;
    auto it = map_.landmarks.find(s.landmark_id);
    // After one match the mixture mean sits between init_depth and the match; the match's
    // own depth is where the landmark reprojects onto it. Not in the run's first map (see
    // first_map_).
    const double depth = s.updates == 1 && !first_map_ ? s.measured_depth : s.depth();
    if (it != map_.landmarks.end())
      it->second->p_w = s.keyframe->T_cw.inverse() * (s.feature.f * depth);
  }
  for (const Seed& s : converged) {
    const Vec3 p_w = s.keyframe->T_cw.inverse() * (s.feature.f * s.depth());
    if (s.landmark_id >= 0) {
      auto it = map_.landmarks.find(s.landmark_id);
      if (it == map_.landmarks.end()) continue;
      it->second->p_w = p_w;
      it->second->converged = true;
      pending_landmarks_.push_back({s.landmark_id, p_w, true, s.keyframe->id, s.feature.px, s.feature.f});
      continue;
    }
    if (std::find(map_.keyframes.begin(), map_.keyframes.end(), s.keyframe) == map_.keyframes.end())
      continue;  // its keyframe has left the map
    LandmarkPtr lm = map_.addLandmark(p_w, true, s.track_id);
    Feature ftr = s.feature;
    ftr.landmark_id = lm->id;
    s.keyframe->features.push_back(ftr);
    lm->observations.push_back({s.keyframe, static_cast<int>(s.keyframe->features.size()) - 1});
    pending_landmarks_.push_back({lm->id, p_w, true, s.keyframe->id, ftr.px, ftr.f});
  }
}

void SemiDirectFrontend::addKeyframe(const FramePtr& frame, FrameResult* result) {
  frame->is_keyframe = true;
  frames_since_keyframe_ = 0;
  KeyframeBundle bundle;
  bundle.keyframe_id = frame->id;
  bundle.t = frame->t;
  bundle.T_WB = cameraToBody(frame->T_cw);
  std::vector<bool> occupied(grid_.cells(), false);
  for (std::size_t i = 0; i < frame->features.size(); ++i) {
    const Feature& f = frame->features[i];
    map_.landmarks.at(f.landmark_id)->observations.push_back({frame, static_cast<int>(i)});
    bundle.observations.push_back({f.landmark_id, f.px, f.f, f.level});
    const int cell = grid_.cellIndex(f.px);
    if (cell >= 0) occupied[cell] = true;
  }
  // New seeds where the map has no landmarks, initialized at this frame's scene depth.
  double median_depth = options_.init_depth, min_depth = options_.init_min_depth;
  sceneDepth(*frame, map_, &median_depth, &min_depth);
  std::vector<Feature> fresh;
  for (const Corner& c : detectCorners(frame->pyramid, options_.detector, grid_, occupied))
    fresh.push_back({c.px, camera_.unproject(c.px), c.level, -1});
  const std::vector<int> seed_ids =
      depth_filter_.addKeyframe(frame, fresh, median_depth, std::max(0.5 * min_depth, 0.1));
  // Each seed's matches are reported under a landmark id reserved now, which its landmark keeps.
  for (std::size_t i = 0; i < fresh.size(); ++i) {
    const int track = map_.next_landmark_id++;
    depth_filter_.setTrackId(seed_ids[i], track);
    seed_matches_.push_back({track, fresh[i].px, fresh[i].level, 0});
  }
  map_.keyframes.push_back(frame);
  while (static_cast<int>(map_.keyframes.size()) > options_.max_keyframes) {
    std::vector<FramePtr> others(map_.keyframes.begin(), map_.keyframes.end() - 1);
    const FramePtr drop = farthestKeyframe(*frame, others);
    depth_filter_.removeSeedsOf(drop);
    map_.removeKeyframe(drop);
  }
  bundle.new_landmarks = std::move(pending_landmarks_);
  pending_landmarks_.clear();
  result->keyframe = std::move(bundle);
}

void SemiDirectFrontend::appendSeedTracks(const Frame& frame,
                                          std::vector<KeyframeBundle::Observation>* observations) const {
  // One observation per grid cell, as the reprojector matches landmarks: cells of matched
  // landmarks are taken; in a free cell the seed with the most depth updates.
  std::vector<bool> taken(grid_.cells(), false);
  for (const Feature& f : frame.features) {
    const int c = grid_.cellIndex(f.px);
    if (c >= 0) taken[c] = true;
  }
  std::set<int> seen;
  for (const auto& o : *observations) seen.insert(o.landmark_id);
  std::vector<int> best(grid_.cells(), -1);
  for (std::size_t i = 0; i < seed_matches_.size(); ++i) {
    const DepthFilter::Match& m = seed_matches_[i];
    const int c = grid_.cellIndex(m.px);
    if (c < 0 || taken[c] || seen.count(m.track_id)) continue;
    if (best[c] < 0 || m.updates > seed_matches_[best[c]].updates) best[c] = static_cast<int>(i);
  }
  for (int i : best) {
    if (i < 0) continue;
    const DepthFilter::Match& m = seed_matches_[i];
    observations->push_back({m.track_id, m.px, camera_.unproject(m.px), m.level});
  }
}

int SemiDirectFrontend::convergedLandmarks() const {
  int n = 0;
  for (const auto& [id, lm] : map_.landmarks) n += lm->converged;
  return n;
}

void SemiDirectFrontend::applyBackendEstimate(const BackendEstimate& estimate) {
  for (const FramePtr& kf : map_.keyframes) {
    auto it = estimate.keyframe_T_WB.find(kf->id);
    if (it == estimate.keyframe_T_WB.end()) continue;
    const Pose T_cw_new = bodyToCamera(it->second);
    // Keep the last frame rigidly attached to the newest corrected keyframe.
    if (last_frame_ && kf == map_.keyframes.back() && last_frame_ != kf)
      last_frame_->T_cw = last_frame_->T_cw * kf->T_cw.inverse() * T_cw_new;
    kf->T_cw = T_cw_new;
  }
  for (const auto& [id, p_w] : estimate.landmark_p_W) {
    auto it = map_.landmarks.find(id);
    if (it != map_.landmarks.end()) it->second->p_w = p_w;
  }
}

}  // namespace hdvio::frontend
