#include "hdvio/run/visual_image_runner.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "hdvio/backend/vio_starter.h"
#include "hdvio/core/error.h"
#include "hdvio/factors/imu_preintegration.h"
#include "hdvio/frontend/gyro_prior.h"
#include "hdvio/frontend/semi_direct_frontend.h"
#include "hdvio/io/image.h"
#include "hdvio/io/image_prefetcher.h"
#include "hdvio/run/init_feature_tracker.h"
#include "hdvio/run/progress.h"

namespace hdvio::run {
namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The backend's latest state carried forward to t with the IMU (what the frontend's sparse
// alignment starts from).
Pose predictPose(const NavState& s, const std::vector<ImuSample>& imu, Timestamp t,
                 const ImuNoiseParams& params) {
  if (t <= s.t) return s.T_WB;
  const PreintegratedImu pim = PreintegratedImu::integrate(imu, s.t, t, s.bias, params);
  const double dt = pim.dt();
  const Mat3 R = s.T_WB.R();
  return Pose(Mat3(R * pim.deltaR()), s.T_WB.p + s.v_W * dt + 0.5 * params.gravity * dt * dt +
                                          R * pim.deltaP());
}

// Backend window poses at the frontend's keyframe times and the backend's landmarks.
frontend::BackendEstimate backendEstimate(const VioBackend& backend,
                                          const frontend::SemiDirectFrontend& fe) {
  frontend::BackendEstimate est;
  const std::vector<NavState> window = backend.windowStates();
  for (const auto& kf : fe.map().keyframes) {
    const auto it = std::find_if(window.begin(), window.end(),
                                 [&](const NavState& s) { return s.t == kf->t; });
    if (it != window.end()) est.keyframe_T_WB[kf->id] = it->T_WB;
  }
  const Values& values = backend.smoother().estimate();
  for (const auto& [id, lm] : fe.map().landmarks)
    if (values.exists(symbols::L(id))) est.landmark_p_W[id] = values.vec3(symbols::L(id));
  return est;
}

void logStart(const VioRunOutput& out, Timestamp first_image_t) {
  std::fprintf(stderr, "\nhdvio_run: started from the %s initialization at t=%.3f s",
               toString(out.start).c_str(), toSeconds(out.start_t));
  if (out.vi_init_attempts == 0) {
    std::fprintf(stderr, "\n");
    return;
  }
  const ViInitResult& r = out.vi_init;
  if (r.success)
    std::fprintf(stderr, " (%.2f s of images, attempt %d: parallax %.1f deg, reprojection "
                         "%.2f px, scale std %.1f %%)\n",
                 secondsBetween(first_image_t, out.start_t), out.vi_init_attempts, r.parallax_deg,
                 r.reprojection_rms_px, 100.0 * r.scale_relative_std);
  else
    std::fprintf(stderr, " (visual-inertial: %d attempts, last: %s)\n", out.vi_init_attempts,
                 r.reason.c_str());
}

bool plausible(const NavState& s) {
  return s.T_WB.p.allFinite() && s.T_WB.q.coeffs().allFinite() && s.v_W.allFinite() &&
         s.v_W.norm() < 100.0;
}

}  // namespace

ImageRunOutput runVioOnImages(const Sequence& seq, const VioBackendOptions& options,
                              const VioRunOptions& run, const VisualFrontendConfig& config,
                              ResidualForceSource residual_force, bool log) {
  if (!seq.hasImages())
    throw InputError(seq.source, 0, "sequence has no camera calibration or no cam0 images");
  if (seq.imu.empty()) throw InputError(seq.source, 0, "sequence has no IMU data");
  const std::vector<ThrustSample> thrust = thrustSamples(seq);
  if (usesDynamics(options.method) && thrust.empty())
    throw InputError(seq.source, 0, "method '" + toString(options.method) +
                                        "' needs thrust (thrust0 or rotor0 with calibration)");

  VioBackendOptions opts = options;
  if (!run.init_from_groundtruth) {
    // Without ground truth the first velocity and tilt are guesses: let vision and IMU fix them.
    opts.init_velocity_sigma = std::max(opts.init_velocity_sigma, run.guess_velocity_sigma);
    opts.init_tilt_sigma = std::max(opts.init_tilt_sigma, run.guess_tilt_sigma);
  }
  VioBackend backend(opts, CameraModel::fromCalibration(*seq.camera), seq.camera->T_BS,
                     std::move(residual_force));
  frontend::SemiDirectFrontend fe(*seq.camera, config.options);
  // The first state: the same policy as on tracks; the VI initialization gets KLT tracks,
  // since the frontend can only start its map at a known (metric) pose.
  VioStarter starter(seq, run, opts.imu);
  InitFeatureTracker init_tracker;

  ImageRunOutput out;
  std::size_t imu_next = 0, thrust_next = 0;
  const auto feed_until = [&](Timestamp t) {
    while (imu_next < seq.imu.size() && seq.imu[imu_next].t <= t)
      backend.addImu(seq.imu[imu_next++]);
    while (thrust_next < thrust.size() && thrust[thrust_next].t <= t)
      backend.addThrust(thrust[thrust_next++]);
  };
  Progress progress(toString(options.method) + " (images)", seq.images.front().t,
                    seq.images.back().t);
  bool lost = false;
  frontend::TrackingStage prev_stage = frontend::TrackingStage::kInitializing;
  int lost_run = 0;
  Timestamp prev_image_t = 0;
  double backend_s = 0.0;
  // Decoding runs on one I/O thread ahead of the estimator; load_ms is what this thread waited.
  // Each image is checked against the calibration (size, 8-bit, complete file): exit 2 at the image.
  const CameraCalibration* camera = &*seq.camera;
  io::ImagePrefetcher images(seq.images, 4,
                             [camera](const ImageRef& r) { return io::loadImage(r, camera); });
  for (const ImageRef& ref : seq.images) {
    if (log) progress.update(ref.t);
    feed_until(ref.t);
    const bool first = !backend.initialized();
    const double waited_before = images.waitSeconds();
    const cv::Mat pixels = images.take();
    const double load_ms = 1e3 * (images.waitSeconds() - waited_before);
    bool load_counted = false;  // an image the initialization tracker saw counts there
    if (first) {
      FrameObservations tracks{ref.t, {}};
      if (starter.needsObservations()) {
        load_counted = true;
        out.load_time_s += load_ms * 1e-3;
        ++out.init_images;
        const auto t_init = Clock::now();
        tracks = init_tracker.track(ref.t, pixels);
        out.init_time_s += secondsSince(t_init);
      }
      const auto t_init = Clock::now();
      const std::optional<NavState> initial = starter.addFrame(tracks);
      out.init_time_s += secondsSince(t_init);
      if (!initial) continue;
      backend.initialize(*initial);
      out.vio.start = starter.kind();
      out.vio.start_t = ref.t;
      out.vio.visual_inertial_start = out.vio.start == StartKind::kVisualInertial;
      out.vio.vi_init_attempts = starter.viInitAttempts();
      if (const ViInitResult* r = starter.viInitResult()) out.vio.vi_init = *r;
      if (log) logStart(out.vio, seq.images.front().t);
    }
    ImageFrameRecord rec;
    rec.t = ref.t;
    rec.load_ms = load_counted ? 0.0 : load_ms;
    frontend::ImageFrame image{ref.t, pixels};

    const NavState latest = backend.latestState();
    frontend::TrackingPrior prior;
    if (!first) prior.q_prev_cur = frontend::integrateGyro(seq.imu, prev_image_t, ref.t,
                                                           latest.bias.head<3>());
    if (first || config.backend_pose_prior || fe.wantsPosePrior())
      prior.T_WB = predictPose(latest, seq.imu, ref.t, opts.imu);
    prev_image_t = ref.t;
    auto t0 = Clock::now();
    const frontend::FrameResult r = fe.track(image, prior);
    rec.frontend_ms = 1e3 * secondsSince(t0);
    rec.stage = r.stage;
    rec.tracked = r.tracked;
    rec.tracked_features = static_cast<int>(r.observations.size());
    rec.frontend_keyframe = r.keyframe ? 1 : 0;
    // A new map: discarded and rebuilt on this image, or started after a failed attempt.
    rec.reinitialized = !first && r.tracked &&
                        (r.reinitialized || prev_stage == frontend::TrackingStage::kInitializing);
    out.reinitializations += rec.reinitialized ? 1 : 0;
    prev_stage = r.stage;
    rec.used_by_backend =
        r.tracked && rec.tracked_features >= config.min_features_for_backend;

    FrameObservations frame{ref.t, {}};
    if (rec.used_by_backend)
      for (const auto& o : r.observations) frame.features.push_back({o.landmark_id, o.px});

    t0 = Clock::now();
    FrameResult br;
    if (first) {
      // The first state comes from the initialization; its observations cannot enter the
      // backend (it has no frame before this one), the frontend keeps them as keyframe 0.
      br.processed = true;
      br.keyframe = true;
      br.state = backend.latestState();
    } else {
      br = backend.addFrame(frame);
    }
    if (br.processed && config.backend_feedback)
      fe.applyBackendEstimate(backendEstimate(backend, fe));
    backend_s += secondsSince(t0);
    out.frontend_time_s += rec.frontend_ms * 1e-3;
    out.load_time_s += rec.load_ms * 1e-3;
    out.images.push_back(rec);
    if (br.processed) {
      if (!plausible(br.state))
        throw std::runtime_error("hdvio_run: the backend diverged at t=" +
                                 std::to_string(toSeconds(ref.t)) + " s (non-finite or > 100 m/s)");
      out.vio.frames.push_back(br);
      out.vio.states.push_back(br.state);
    }

    if (!rec.used_by_backend && !first) {
      ++out.lost_images;
      ++lost_run;
      if (!lost && log)
        std::fprintf(stderr, "\nhdvio_run: frontend lost at t=%.3f s (%s, %d features): "
                             "backend continues on IMU%s\n",
                     toSeconds(ref.t), frontend::toString(r.stage).c_str(), rec.tracked_features,
                     usesDynamics(options.method) ? " and dynamics" : "");
      lost = true;
    } else if (lost) {
      if (log)
        std::fprintf(stderr, "hdvio_run: frontend tracking again at t=%.3f s after %d lost "
                             "images%s\n",
                     toSeconds(ref.t), lost_run, rec.reinitialized ? " (map re-initialized)" : "");
      lost = false;
      lost_run = 0;
    }
  }
  if (log) progress.finish();
  out.vio.backend_time_s = backend_s;
  if (!starter.started()) throw InputError(seq.source, 0, starter.notStartedReason());
  if (out.vio.frames.empty())
    throw InputError(seq.source, 0, "no image could be processed (images outside the IMU data?)");
  if (log)
    std::fprintf(stderr, "hdvio_run: frontend saw %zu images, %d lost (IMU-only backend steps), "
                         "%d map re-initializations\n",
                 out.images.size(), out.lost_images, out.reinitializations);
  return out;
}

}  // namespace hdvio::run
