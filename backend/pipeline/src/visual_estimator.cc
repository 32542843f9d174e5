#include "hdvio/pipeline/visual_estimator.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <utility>

#include "hdvio/frontend/gyro_prior.h"
#include "hdvio/pipeline/frontend_handshake.h"
#include "hdvio/pipeline/residual_force_adapter.h"

namespace hdvio {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The first external force is no guess of the start: hdvio measures it over the static
// window before the first state (accelerometer minus model).
VisualEstimatorOptions withStartPriors(VisualEstimatorOptions o) {
  if (!o.start.init_from_groundtruth) o.backend.init_force_window_s = o.start.static_init_window_s;
  return o;
}

// The first state's velocity and tilt priors. A static start's zero velocity and gravity
// direction are guesses: loose, vision and IMU fix them. Ground truth and the visual-inertial
// initialization are estimates within the backend's init sigmas (0.1 m/s, 0.02 rad; the VI
// initialization's largest errors on the rendered start flights are 0.06-0.10 m/s and
// 0.35-0.87 deg, docs/vi_initialization.md); loose priors there let a young map pull the
// window away (docs/vi_initialization.md "Start policy").
VioBackend::StartUncertainty startPriorFor(StartKind kind, const VisualEstimatorOptions& o) {
  VioBackend::StartUncertainty u{o.backend.init_velocity_sigma, o.backend.init_tilt_sigma};
  if (kind == StartKind::kGroundTruth || kind == StartKind::kVisualInertial) return u;
  u.velocity_sigma = std::max(u.velocity_sigma, o.start.guess_velocity_sigma);
  u.tilt_sigma = std::max(u.tilt_sigma, o.start.guess_tilt_sigma);
  return u;
}

bool plausible(const NavState& s) {
  return s.T_WB.p.allFinite() && s.T_WB.q.coeffs().allFinite() && s.v_W.allFinite() &&
         s.v_W.norm() < 100.0;
}

FrameResult firstResult(const VioBackend& backend) {
  FrameResult first;
  first.processed = true;
  first.keyframe = true;
  first.state = backend.latestState();
  return first;
}

}  // namespace

VisualEstimator::VisualEstimator(const VisualEstimatorOptions& options,
                                 const CameraCalibration& camera,
                                 std::shared_ptr<const learned::ResidualForceProvider> residual_force,
                                 GroundTruthFn ground_truth)
    : options_(withStartPriors(options)),
      camera_(camera),
      provider_(std::move(residual_force)),
      backend_(options_.backend, CameraModel::fromCalibration(camera), camera.T_BS,
               residualForceSource(provider_, &imu_, &thrust_)),
      starter_(camera, imu_, options_.start, options_.backend.imu, std::move(ground_truth)) {}

void VisualEstimator::addImu(const ImuSample& s) {
  if (imu_.empty() || s.t > imu_.back().t) imu_.push_back(s);
  backend_.addImu(s);
}

void VisualEstimator::addThrust(const ThrustSample& s) {
  if (thrust_.empty() || s.t > thrust_.back().t) thrust_.push_back(s);
  backend_.addThrust(s);
}

std::optional<FrameResult> VisualEstimator::addTrackedFrame(const FrameObservations& frame) {
  if (!backend_.initialized()) {
    const std::optional<NavState> initial = starter_.addFrame(frame);
    if (!initial) return std::nullopt;
    start_uncertainty_ = startPriorFor(starter_.kind(), options_);
    backend_.initialize(*initial, start_uncertainty_);
    return firstResult(backend_);
  }
  const FrameResult r = backend_.addFrame(frame);
  if (!r.processed) return std::nullopt;
  return r;
}

ImageStep VisualEstimator::addImage(Timestamp t, const cv::Mat& pixels) {
  const VisualFrontendConfig& config = options_.frontend;
  if (!frontend_) frontend_ = std::make_unique<frontend::SemiDirectFrontend>(camera_, config.options);
  frontend::SemiDirectFrontend& fe = *frontend_;
  ImageStep step;
  const bool first = !backend_.initialized();
  if (first) {
    // The start's policy as on tracks; the VI initialization gets KLT tracks, since the
    // frontend can only start its map at a known (metric) pose.
    FrameObservations tracks{t, {}};
    if (starter_.needsObservations()) {
      ++init_images_;
      const auto t_init = Clock::now();
      tracks = init_tracker_.track(t, pixels);
      init_s_ += secondsSince(t_init);
    }
    const auto t_init = Clock::now();
    const std::optional<NavState> initial = starter_.addFrame(tracks);
    init_s_ += secondsSince(t_init);
    if (!initial) return step;
    start_uncertainty_ = startPriorFor(starter_.kind(), options_);
    backend_.initialize(*initial, start_uncertainty_);
    step.first = true;
  }
  step.started = true;
  ImageFrameRecord& rec = step.record;
  rec.t = t;

  // Pose prior: the gyro rotation since the previous image and the IMU-predicted pose.
  const NavState latest = backend_.latestState();
  frontend::TrackingPrior prior;
  if (!first) prior.q_prev_cur = frontend::integrateGyro(imu_, prev_image_t_, t, latest.bias.head<3>());
  if (first || config.backend_pose_prior || fe.wantsPosePrior())
    prior.T_WB = predictPose(latest, imu_, t, options_.backend.imu);
  prev_image_t_ = t;
  auto t0 = Clock::now();
  const frontend::FrameResult r = fe.track(frontend::ImageFrame{t, pixels}, prior);
  rec.frontend_ms = 1e3 * secondsSince(t0);
  rec.frontend_stages = r.timing;
  rec.stage = r.stage;
  rec.tracked = r.tracked;
  rec.tracked_features = static_cast<int>(r.observations.size());
  rec.frontend_keyframe = r.keyframe ? 1 : 0;
  // A new map: discarded and rebuilt on this image, or started after a failed attempt.
  rec.reinitialized = !first && r.tracked &&
                      (r.reinitialized || prev_stage_ == frontend::TrackingStage::kInitializing);
  prev_stage_ = r.stage;
  rec.used_by_backend = r.tracked && rec.tracked_features >= config.min_features_for_backend;
  frontend_s_ += rec.frontend_ms * 1e-3;

  step.observations = r.observations;
  if (r.keyframe) step.new_landmarks = r.keyframe->new_landmarks;
  FrameObservations frame{t, {}};
  if (rec.used_by_backend)
    for (const auto& o : r.observations) frame.features.push_back({o.landmark_id, o.px});

  t0 = Clock::now();
  // The first state comes from the initialization; its observations cannot enter the backend
  // (it has no frame before this one), the frontend keeps them as keyframe 0.
  const FrameResult br = first ? firstResult(backend_) : backend_.addFrame(frame);
  // Feedback: the optimized window keyframes and landmarks into the frontend's map.
  if (br.processed && config.backend_feedback) fe.applyBackendEstimate(backendEstimate(backend_, fe));
  rec.backend_ms = 1e3 * secondsSince(t0);
  backend_s_ += rec.backend_ms * 1e-3;
  if (br.processed) {
    if (!plausible(br.state))
      throw std::runtime_error("hdvio_run: the backend diverged at t=" +
                               std::to_string(toSeconds(t)) + " s (non-finite or > 100 m/s)");
    step.result = br;
  }
  return step;
}

NavState VisualEstimator::state() const {
  if (!backend_.initialized()) throw std::logic_error("VisualEstimator: no state before the start");
  return backend_.latestState();
}

bool VisualEstimator::hasModelForce() const {
  return provider_ || (usesDynamics(options_.backend.method) && options_.backend.dynamics.drag.enabled());
}

Vec3 VisualEstimator::modelForceAt(const NavState& s) const {
  Vec3 f = provider_ ? residualForceAtState(*provider_, imu_, thrust_, s) : Vec3::Zero();
  const DragLaw& drag = options_.backend.dynamics.drag;
  if (usesDynamics(options_.backend.method) && drag.enabled()) {
    // The law's rotor term needs the thrust: the latest sample at or before the state.
    auto after = std::upper_bound(thrust_.begin(), thrust_.end(), s.t,
                                  [](Timestamp t, const ThrustSample& x) { return t < x.t; });
    const double thrust = after == thrust_.begin() ? DragLaw::kHoverThrust : std::prev(after)->thrust.norm();
    f += drag.force(s.T_WB.R().transpose() * s.v_W, thrust);
  }
  return f;
}

ForceEstimate VisualEstimator::forceEstimate() const {
  const NavState s = state();
  ForceEstimate f;
  f.t = s.t;
  f.external_B = s.T_WB.q.conjugate() * s.f_ext_W;
  f.model_B = modelForceAt(s);
  return f;
}

}  // namespace hdvio
