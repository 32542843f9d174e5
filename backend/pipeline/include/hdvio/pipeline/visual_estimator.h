#pragma once
// One object per visual method family (vio, vimo, vid, hdvio): a program feeds it measurements
// in time order and asks for the state, as OpenVINS's VioManager. Inside: the start
// (VioStarter), the sliding-window backend (VioBackend), for images the semi-direct frontend
// with the frontend-backend handshake (frontend_handshake.h) and, before the first state, the
// KLT initialization tracker; for hdvio the learned residual-force provider adapted to the
// backend (residual_force_adapter.h). Deterministic: one image at a time, frontend then backend.
//
// Feeding: IMU (and thrust, for vimo / vid / hdvio) up to a frame's time first, then the frame:
// either addTrackedFrame (landmark observations, e.g. the simulator's tracks) or addImage
// (cam0 pixels). hdvio_run feeds whole sequences through visual_sequence_runner.h.
//
// Images: until the start is decided, images go to the KLT tracker whose tracks feed the
// visual-inertial initialization; the frontend then starts its map on the image of the first
// state, at that metric, gravity-aligned pose. An image the frontend cannot track (or with too
// few features) becomes an IMU-only (and dynamics) step of the backend; the frontend
// relocalizes and, after a while, re-initializes its map at the backend's pose.
#include <memory>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "hdvio/backend/vio_backend.h"
#include "hdvio/frontend/semi_direct_frontend.h"
#include "hdvio/learned/residual_force_provider.h"
#include "hdvio/pipeline/init_feature_tracker.h"
#include "hdvio/pipeline/visual_frontend_config.h"
#include "hdvio/pipeline/visual_start.h"

namespace hdvio {

struct VisualEstimatorOptions {
  VioBackendOptions backend;
  VioRunOptions start;
  VisualFrontendConfig frontend;  // addImage only
};

// What happened to one image after the start, for logs and tests.
struct ImageFrameRecord {
  Timestamp t = 0;
  frontend::TrackingStage stage = frontend::TrackingStage::kInitializing;
  bool tracked = false;
  bool reinitialized = false;
  bool used_by_backend = false;  // observations were given to the backend
  int tracked_features = 0;
  int frontend_keyframe = 0;     // 1 when the frontend took a keyframe
  double frontend_ms = 0.0;      // wall time of SemiDirectFrontend::track
  frontend::FrameTiming frontend_stages;  // its parts (wall ms), as the frontend measured them
  double backend_ms = 0.0;       // wall time of the backend step and its feedback to the frontend
  double load_ms = 0.0;          // filled by whoever decoded the image (not the estimator)
};

// addImage's answer. Before the start (started false) the image only fed the initialization.
struct ImageStep {
  bool started = false;
  bool first = false;  // this image carries the first state (its observations start the map)
  ImageFrameRecord record;             // when started
  std::optional<FrameResult> result;   // when the backend produced a state for this image
  // The frontend's observations of this image (empty when not tracked) and the landmarks its
  // keyframe added, for diagnostics (hdvio_feature_truth); the backend got the observations
  // when record.used_by_backend.
  std::vector<frontend::KeyframeBundle::Observation> observations;
  std::vector<frontend::KeyframeBundle::NewLandmark> new_landmarks;
};

// Non-thrust forces at a state, body (IMU) frame, m/s^2.
struct ForceEstimate {
  Timestamp t = 0;
  Vec3 external_B = Vec3::Zero();  // the estimated external force (vimo, vid, hdvio)
  Vec3 model_B = Vec3::Zero();     // hdvio: learned residual + drag law at the state's velocity
  Vec3 total() const { return external_B + model_B; }
};

class VisualEstimator {
 public:
  // residual_force: hdvio's learned provider (null: none). ground_truth: for
  // start.init_from_groundtruth. Throws InputError for a missing ground truth it needs.
  VisualEstimator(const VisualEstimatorOptions& options, const CameraCalibration& camera,
                  std::shared_ptr<const learned::ResidualForceProvider> residual_force = nullptr,
                  GroundTruthFn ground_truth = nullptr);
  VisualEstimator(const VisualEstimator&) = delete;  // the backend holds views of the buffers
  VisualEstimator& operator=(const VisualEstimator&) = delete;

  void addImu(const ImuSample& sample);
  void addThrust(const ThrustSample& sample);
  // The state at frame.t when this frame produced one (the first state included).
  std::optional<FrameResult> addTrackedFrame(const FrameObservations& frame);
  // pixels: 8-bit grayscale, raw (distorted), as the calibration. Throws std::runtime_error
  // when the backend diverges (non-finite or faster than 100 m/s).
  ImageStep addImage(Timestamp t, const cv::Mat& pixels);

  bool initialized() const { return backend_.initialized(); }
  // The latest estimate; throws std::logic_error before the first state.
  NavState state() const;
  ForceEstimate forceEstimate() const;
  // The model part of the force (ForceEstimate::model_B) at any estimated state, from the
  // samples received around its time; zero without a provider or drag law.
  Vec3 modelForceAt(const NavState& s) const;
  bool hasModelForce() const;

  const VioStarter& starter() const { return starter_; }
  // The first state's velocity and tilt prior sigmas, chosen by the kind of start.
  const VioBackend::StartUncertainty& startUncertainty() const { return start_uncertainty_; }
  const VioBackendOptions& backendOptions() const { return options_.backend; }
  // Wall time in the backend (frames and feedback), the frontend, and before the first state
  // (KLT tracking and initialization attempts); images given to the KLT tracker.
  double backendSeconds() const { return backend_s_; }
  double frontendSeconds() const { return frontend_s_; }
  double initSeconds() const { return init_s_; }
  int initImages() const { return init_images_; }

 private:
  VisualEstimatorOptions options_;  // backend: with the start's guessed prior sigmas
  CameraCalibration camera_;
  std::shared_ptr<const learned::ResidualForceProvider> provider_;
  std::vector<ImuSample> imu_;
  std::vector<ThrustSample> thrust_;
  VioBackend backend_;
  VioStarter starter_;
  std::unique_ptr<frontend::SemiDirectFrontend> frontend_;  // on the first image
  VioBackend::StartUncertainty start_uncertainty_;
  InitFeatureTracker init_tracker_;
  frontend::TrackingStage prev_stage_ = frontend::TrackingStage::kInitializing;
  Timestamp prev_image_t_ = 0;
  double backend_s_ = 0.0, frontend_s_ = 0.0, init_s_ = 0.0;
  int init_images_ = 0;
};

}  // namespace hdvio
