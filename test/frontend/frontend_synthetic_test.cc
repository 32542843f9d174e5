// The whole frontend on a rendered flight through the textured room: tracking, keyframes,
// depth filters turning into landmarks, tracking-loss detection and re-initialization.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>

#include "hdvio/core/error.h"
#include "hdvio/frontend/semi_direct_frontend.h"
#include "synthetic_room.h"

namespace hdvio::frontend {
namespace {

// Body = camera rotated (T_BS is not identity, as on real rigs).
Pose bodyToCameraExtrinsics() { return Pose(quatExp(Vec3(0.0, 0.0, M_PI / 2)), Vec3(0.02, -0.01, 0.0)); }

Pose cameraPoseAt(int k) {  // 20 Hz; ~0.8 m/s sideways/forward with yaw and some pitch motion
  const double s = 0.05 * k;
  return test::lookingForward(Vec3(-2.0 + 0.3 * s, 0.8 - 0.7 * s, 1.3 + 0.1 * std::sin(2.0 * s)),
                              0.25 - 0.15 * s, 0.2 + 0.05 * std::sin(3.0 * s));
}

class FrontendSyntheticFlight : public ::testing::Test {
 protected:
  FrontendSyntheticFlight() : camera_(CameraModel::fromCalibration(calibration())) {}
  static CameraCalibration calibration() {
    CameraCalibration c = test::syntheticCalibration();
    c.T_BS = bodyToCameraExtrinsics();
    return c;
  }
  Pose bodyPose(int k) const { return cameraPoseAt(k) * calibration().T_BS.inverse(); }
  ImageFrame image(int k) const {
    return {1'000'000'000LL + k * 50'000'000LL, room_.render(camera_, cameraPoseAt(k))};
  }
  TrackingPrior prior(const SemiDirectFrontend& fe, int k) const {
    TrackingPrior p;
    if (k > 0) p.q_prev_cur = bodyPose(k - 1).q.conjugate() * bodyPose(k).q;
    if (fe.wantsPosePrior()) p.T_WB = bodyPose(k);  // stands in for the backend
    return p;
  }
  // Observations of image b more than 2 px from their landmark's true point (where the
  // landmark's ray from the map's first camera a meets the room).
  int farOff(const SemiDirectFrontend& fe, const FrameResult& r, const Pose& a, const Pose& b) const {
    int far_off = 0;
    for (const auto& o : r.observations) {
      const Vec3 p_w = fe.map().landmarks.at(o.landmark_id)->p_w;
      Vec3 hit;
      room_.castRay(a.p, (p_w - a.p).normalized(), &hit);
      Vec2 truth;
      if (!camera_.project(b.inverse() * hit, &truth)) {
        ADD_FAILURE() << "landmark " << o.landmark_id << " is not in view of b";
        continue;
      }
      far_off += (o.px - truth).norm() > 2.0;
    }
    return far_off;
  }
  test::SyntheticRoom room_;
  CameraModel camera_;
};

TEST_F(FrontendSyntheticFlight, TracksEveryImageAndConvergesNewLandmarks) {
  SemiDirectFrontend fe(calibration());
  int keyframes = 0, converged_new = 0, gt_priors = 0;
  double max_pos_err = 0.0, max_rot_err_deg = 0.0;
  constexpr int kFrames = 40;
  for (int k = 0; k < kFrames; ++k) {
    gt_priors += fe.wantsPosePrior();
    const FrameResult r = fe.track(image(k), prior(fe, k));
    ASSERT_TRUE(r.tracked) << "image " << k;
    EXPECT_FALSE(r.reinitialized);
    EXPECT_GE(r.tracked_features, 50) << "image " << k;
    if (r.keyframe) {
      ++keyframes;
      for (const auto& lm : r.keyframe->new_landmarks) converged_new += lm.converged;
      EXPECT_EQ(r.keyframe->keyframe_id, r.frame_id);
    }
    max_pos_err = std::max(max_pos_err, (r.T_WB.p - bodyPose(k).p).norm());
    max_rot_err_deg =
        std::max(max_rot_err_deg, quatLog(r.T_WB.q.conjugate() * bodyPose(k).q).norm() * 180 / M_PI);
  }
  EXPECT_EQ(fe.stage(), TrackingStage::kTracking);
  EXPECT_LE(gt_priors, FrontendOptions().bootstrap_max_frames + 1);
  EXPECT_GE(keyframes, 2);          // the first one and at least one as the camera travels
  EXPECT_GT(converged_new, 50);     // depth filters became landmarks
  EXPECT_LT(max_pos_err, 0.05);     // m, over a 1.5 m flight
  EXPECT_LT(max_rot_err_deg, 0.5);
}

// A keyframe's new features reach the backend from that keyframe on, as observations of their
// seeds' tracks, not only once their depths converged: one observation per grid cell (cells
// of matched landmarks first), within the precision of matched landmarks, and a seed that
// converges becomes the landmark of its track's id.
TEST_F(FrontendSyntheticFlight, SeedsAreObservedFromTheirKeyframeOn) {
  SemiDirectFrontend fe(calibration());
  const int cell = FrontendOptions().detector.cell_size;
  std::map<int, std::pair<int, Vec2>> first;  // id -> image and pixel of its first observation
  std::set<int> seed_ids;
  int seed_observations = 0, far_off = 0, checked = 0, same_cell = 0;
  for (int k = 0; k < 40; ++k) {
    const FrameResult r = fe.track(image(k), prior(fe, k));
    ASSERT_TRUE(r.tracked) << "image " << k;
    // Cells of matched landmarks (a landmark's refined pixel may leave the cell it was searched
    // in), then each seed's: a seed never shares one.
    const auto cellOf = [cell](const Vec2& px) {
      return std::make_pair(static_cast<int>(px.x()) / cell, static_cast<int>(px.y()) / cell);
    };
    std::set<std::pair<int, int>> cells;
    for (const auto& o : r.observations)
      if (fe.map().landmarks.count(o.landmark_id)) cells.insert(cellOf(o.px));
    for (const auto& o : r.observations) {
      const bool seed = fe.map().landmarks.count(o.landmark_id) == 0;
      if (seed) {
        seed_ids.insert(o.landmark_id);
        ++seed_observations;
        same_cell += !cells.insert(cellOf(o.px)).second;
      }
      const auto [it, is_first] = first.emplace(o.landmark_id, std::make_pair(k, o.px));
      if (is_first || !seed) continue;
      // The true point: the first observation's ray from its true camera meets the room.
      const Pose a = cameraPoseAt(it->second.first);
      Vec3 hit;
      room_.castRay(a.p, (a.q * camera_.unproject(it->second.second)).normalized(), &hit);
      Vec2 truth;
      if (!camera_.project(cameraPoseAt(k).inverse() * hit, &truth)) continue;
      ++checked;
      far_off += (o.px - truth).norm() > 2.0;
    }
  }
  int became_landmarks = 0;
  for (int id : seed_ids) became_landmarks += fe.map().landmarks.count(id) > 0;
  std::printf("%d seed observations of %zu seed tracks, %d of %d checked more than 2 px off, "
              "%d became landmarks\n", seed_observations, seed_ids.size(), far_off, checked, became_landmarks);
  EXPECT_EQ(same_cell, 0);
  EXPECT_GT(seed_observations, 200);
  EXPECT_GT(checked, 100);
  EXPECT_LE(far_off, checked / 20);
  EXPECT_GT(became_landmarks, 20);
}

TEST_F(FrontendSyntheticFlight, DetectsLossAndReinitializes) {
  FrontendOptions options;
  SemiDirectFrontend fe(calibration(), options);
  for (int k = 0; k < 12; ++k) ASSERT_TRUE(fe.track(image(k), prior(fe, k)).tracked);
  ASSERT_EQ(fe.stage(), TrackingStage::kTracking);
  // The lens is covered: nothing can be tracked.
  const cv::Mat blank(480, 752, CV_8UC1, cv::Scalar(90));
  int k = 12;
  FrameResult r = fe.track({image(k).t, blank}, prior(fe, k));
  EXPECT_FALSE(r.tracked);
  EXPECT_EQ(r.stage, TrackingStage::kRelocalizing);
  for (++k; k < 12 + options.max_relocalization_frames + 1; ++k)
    r = fe.track({image(k).t, blank}, prior(fe, k));
  EXPECT_FALSE(r.tracked);
  EXPECT_EQ(r.stage, TrackingStage::kInitializing);  // gave up relocalizing; map discarded
  EXPECT_TRUE(fe.map().landmarks.empty());
  EXPECT_TRUE(fe.wantsPosePrior());
  // The view comes back: the frontend builds a new map from the (backend) pose prior.
  r = fe.track(image(k), prior(fe, k));
  EXPECT_TRUE(r.tracked);
  EXPECT_TRUE(r.keyframe.has_value());
  EXPECT_LT((r.T_WB.p - bodyPose(k).p).norm(), 1e-9);
  for (++k; k < 30; ++k) {
    r = fe.track(image(k), prior(fe, k));
    EXPECT_TRUE(r.tracked) << "image " << k;
  }
  EXPECT_LT((r.T_WB.p - bodyPose(k - 1).p).norm(), 0.05);
}

// max_relocalization_frames: 0 (the image configs): with the backend's pose there is nothing to
// relocalize against, so the image that loses the map starts a new one and is not lost.
TEST_F(FrontendSyntheticFlight, ReinitializesOnTheLostImageWhenRelocalizationIsOff) {
  // The camera turned half around between two images: the map is behind it.
  const Pose turned = cameraPoseAt(12) * Pose(quatExp(Vec3(0.0, M_PI, 0.0)), Vec3::Zero());
  const ImageFrame behind{image(12).t, room_.render(camera_, turned)};
  TrackingPrior prior;
  prior.T_WB = turned * calibration().T_BS.inverse();
  for (const int frames : {5, 0}) {
    FrontendOptions options;
    options.max_relocalization_frames = frames;
    SemiDirectFrontend fe(calibration(), options);
    for (int k = 0; k < 12; ++k) ASSERT_TRUE(fe.track(image(k), this->prior(fe, k)).tracked);
    ASSERT_EQ(fe.stage(), TrackingStage::kTracking);
    const FrameResult r = fe.track(behind, prior);
    if (frames > 0) {
      EXPECT_FALSE(r.tracked);
      EXPECT_EQ(r.stage, TrackingStage::kRelocalizing);
      continue;
    }
    EXPECT_TRUE(r.tracked);
    EXPECT_TRUE(r.reinitialized);
    ASSERT_TRUE(r.keyframe.has_value());
    EXPECT_EQ(r.stage, TrackingStage::kBootstrapping);
    EXPECT_LT((r.T_WB.p - prior.T_WB->p).norm(), 1e-9);  // the new map starts at the given pose
    EXPECT_GE(r.tracked_features, 50);
  }
}

// A new map on the backend's pose whose provisional landmarks miss in the next image: the
// camera moved 0.2 m sideways and the room is ~7 m away, not init_depth's 3 m, so they are
// ~20 px off. A frontend that needs 100 matches (standing in for a faster flight, where even
// fewer hold) then searches the seeds along their epipolar lines on the given pose and matches
// the landmarks where the seeds found them. Without that second pass: 31 matches, 8 of them
// more than 2 px off their true point. (Limits, measured when written: at 0.6 m the seeds'
// epipolar segments exceed max_search_steps and nothing is gained; with init_depth 1.5 the
// search matched wrong places.)
TEST_F(FrontendSyntheticFlight, NewMapThatMissesSearchesItsSeedsAlongTheEpipolarLines) {
  const Pose a = test::lookingForward(Vec3(-2.0, 0.0, 1.5), 0.1, 0.15);
  const Pose b(a.q, a.p + a.q * Vec3(0.2, 0.0, 0.0));  // along the camera's x axis
  FrontendOptions options;
  options.min_tracked_features = 100;
  SemiDirectFrontend fe(calibration(), options);
  TrackingPrior prior;
  prior.T_WB = a * calibration().T_BS.inverse();
  ASSERT_TRUE(fe.track({1'000'000'000LL, room_.render(camera_, a)}, prior).tracked);
  ASSERT_EQ(fe.stage(), TrackingStage::kBootstrapping);
  prior.T_WB = b * calibration().T_BS.inverse();
  const FrameResult r = fe.track({1'050'000'000LL, room_.render(camera_, b)}, prior);
  ASSERT_TRUE(r.tracked);
  EXPECT_FALSE(r.reinitialized);
  EXPECT_LT((r.T_WB.p - prior.T_WB->p).norm(), 1e-9);  // the given pose is kept
  const int far_off = farOff(fe, r, a, b);
  std::printf("%d matched of %d landmarks, %d more than 2 px off\n", r.tracked_features,
              r.landmarks, far_off);
  EXPECT_GE(r.tracked_features, 100);
  EXPECT_LE(far_off, r.tracked_features / 20);
}

// While a new map bootstraps on the backend's poses, its seeds are searched along their
// epipolar lines on the given pose before the provisional landmarks are matched, so landmarks
// started at init_depth's 3 m in a room ~7 m away are matched where the seeds found them,
// not where the stale depth puts them (a flight at speed: 0.1 m between images, ~10 px; the
// frontend keeps at most max_features 180).
TEST_F(FrontendSyntheticFlight, BootstrappingMatchesLandmarksWhereTheirSeedsWereFound) {
  const Pose a = test::lookingForward(Vec3(-2.0, 0.0, 1.5), 0.1, 0.15);
  SemiDirectFrontend fe(calibration());
  TrackingPrior prior;
  prior.T_WB = a * calibration().T_BS.inverse();
  ASSERT_TRUE(fe.track({1'000'000'000LL, room_.render(camera_, a)}, prior).tracked);
  for (int k = 1; k <= 3; ++k) {
    const Pose b(a.q, a.p + a.q * Vec3(0.1 * k, 0.0, 0.0));
    prior.T_WB = b * calibration().T_BS.inverse();
    const FrameResult r = fe.track({1'000'000'000LL + k * 50'000'000LL, room_.render(camera_, b)}, prior);
    ASSERT_TRUE(r.tracked);
    ASSERT_FALSE(r.reinitialized);
    const int far_off = farOff(fe, r, a, b);
    std::printf("image %d: %d matched of %d landmarks, %d more than 2 px off\n", k,
                r.tracked_features, r.landmarks, far_off);
    // Matching the stale landmarks first held 121 on the first image.
    EXPECT_GE(r.tracked_features, 170);
    EXPECT_LE(far_off, r.tracked_features / 20);
  }
}

// A new map made in flight on the backend's pose while the camera moves and turns fast (0.43 m
// and 6 deg between its first two images, room ~7 m away, init_depth 3 m). After its first match
// a seed's mean sits between init_depth and the match; the provisional landmark placed at the
// match's own depth is found where the seed found it (177 matched when written; placed at the
// seed's mean, 49: the others fail the pose-fixed inlier test). The run's first map (the start,
// at rest, where a first match comes at little parallax and its depth is noisy) keeps the
// seed's mean: there the same images match fewer.
TEST_F(FrontendSyntheticFlight, NewMapAtAFastTurnMatchesWhereItsSeedsWereFound) {
  const Pose a = test::lookingForward(Vec3(-2.0, 0.0, 1.5), 0.1, 0.15);
  const Pose b(a.q * quatExp(Vec3(0.0, 6.0 * M_PI / 180.0, 0.0)), a.p + a.q * Vec3(0.43, 0.0, 0.0));
  for (const bool in_flight : {true, false}) {
    SemiDirectFrontend fe(calibration());
    TrackingPrior prior;
    prior.T_WB = a * calibration().T_BS.inverse();
    Timestamp t = 1'000'000'000LL;
    if (in_flight) {  // a first map, lost: the next one is made in flight
      ASSERT_TRUE(fe.track({t, room_.render(camera_, a)}, prior).tracked);
      fe.reset();
      t += 50'000'000LL;
    }
    ASSERT_TRUE(fe.track({t, room_.render(camera_, a)}, prior).tracked);
    const Pose body_a = *prior.T_WB;
    prior.T_WB = b * calibration().T_BS.inverse();
    prior.q_prev_cur = body_a.q.conjugate() * prior.T_WB->q;
    const FrameResult r = fe.track({t + 50'000'000LL, room_.render(camera_, b)}, prior);
    ASSERT_TRUE(r.tracked);
    ASSERT_FALSE(r.reinitialized);
    const int far_off = farOff(fe, r, a, b);
    std::printf("%s: %d matched of %d landmarks, %d more than 2 px off\n",
                in_flight ? "map made in flight" : "the run's first map", r.tracked_features,
                r.landmarks, far_off);
    if (in_flight) {
      EXPECT_GE(r.tracked_features, 120);
      EXPECT_LE(far_off, r.tracked_features / 20);
    } else {
      EXPECT_LT(r.tracked_features, 100);
    }
  }
}

TEST_F(FrontendSyntheticFlight, FollowsTheBackendsCorrections) {
  SemiDirectFrontend fe(calibration());
  int k = 0;
  for (; k < 15; ++k) ASSERT_TRUE(fe.track(image(k), prior(fe, k)).tracked);
  ASSERT_EQ(fe.stage(), TrackingStage::kTracking);
  // The backend moved the whole map by 0.5 m (e.g. a new gauge): keyframes and landmarks.
  const Pose shift(Quat::Identity(), Vec3(0.5, -0.2, 0.1));
  BackendEstimate estimate;
  for (const FramePtr& kf : fe.map().keyframes)
    estimate.keyframe_T_WB[kf->id] = shift * (kf->T_cw.inverse() * calibration().T_BS.inverse());
  for (const auto& [id, lm] : fe.map().landmarks) estimate.landmark_p_W[id] = shift * lm->p_w;
  fe.applyBackendEstimate(estimate);
  for (; k < 22; ++k) {
    const FrameResult r = fe.track(image(k), prior(fe, k));
    ASSERT_TRUE(r.tracked);
    EXPECT_LT((r.T_WB.p - (shift * bodyPose(k)).p).norm(), 0.03) << "image " << k;
  }
}

TEST_F(FrontendSyntheticFlight, RejectsBadImages) {
  SemiDirectFrontend fe(calibration());
  EXPECT_THROW(fe.track({0, cv::Mat()}), InputError);
  EXPECT_THROW(fe.track({0, cv::Mat(100, 100, CV_8UC1, cv::Scalar(0))}), InputError);
  EXPECT_THROW(fe.track({0, cv::Mat(480, 752, CV_32FC1, cv::Scalar(0))}), InputError);
  fe.track(image(1));
  EXPECT_THROW(fe.track(image(0)), InputError);  // time went backwards
}

}  // namespace
}  // namespace hdvio::frontend
