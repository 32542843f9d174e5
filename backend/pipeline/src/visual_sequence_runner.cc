#include "hdvio/pipeline/visual_sequence_runner.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <random>
#include <string>

#include "hdvio/core/error.h"
#include "hdvio/io/image.h"
#include "hdvio/io/image_prefetcher.h"

namespace hdvio {
namespace {

// The sequence's IMU and thrust in time order into the estimator, up to a time.
class SampleFeeder {
 public:
  SampleFeeder(const Sequence& seq, std::vector<ThrustSample> thrust)
      : seq_(seq), thrust_(std::move(thrust)) {}
  void feedUntil(VisualEstimator* est, Timestamp t) {
    while (imu_next_ < seq_.imu.size() && seq_.imu[imu_next_].t <= t) est->addImu(seq_.imu[imu_next_++]);
    while (thrust_next_ < thrust_.size() && thrust_[thrust_next_].t <= t)
      est->addThrust(thrust_[thrust_next_++]);
  }
  // What is left after the last frame: the model force at the last states looks past them.
  void feedRest(VisualEstimator* est) {
    while (imu_next_ < seq_.imu.size()) est->addImu(seq_.imu[imu_next_++]);
    while (thrust_next_ < thrust_.size()) est->addThrust(thrust_[thrust_next_++]);
  }

 private:
  const Sequence& seq_;
  std::vector<ThrustSample> thrust_;
  std::size_t imu_next_ = 0, thrust_next_ = 0;
};

std::vector<ThrustSample> checkedThrust(const Sequence& seq, VioMethod method) {
  std::vector<ThrustSample> thrust = thrustSamples(seq);
  if (usesDynamics(method) && thrust.empty())
    throw InputError(seq.source, 0, "method '" + toString(method) +
                                        "' needs thrust (thrust0 or rotor0 with calibration)");
  return thrust;
}

GroundTruthFn groundTruthOf(const Sequence& seq) {
  return [&seq](Timestamp t) { return groundTruthState(seq, t); };
}

void recordStart(const VioStarter& starter, Timestamp t, VioRunOutput* out) {
  out->start = starter.kind();
  out->start_t = t;
  out->visual_inertial_start = out->start == StartKind::kVisualInertial;
  out->vi_init_attempts = starter.viInitAttempts();
  if (const ViInitResult* r = starter.viInitResult()) out->vi_init = *r;
}

void recordModelForces(const VisualEstimator& est, VioRunOutput* out) {
  if (!est.hasModelForce()) return;
  for (const NavState& s : out->states) out->model_force_B.push_back(est.modelForceAt(s));
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

}  // namespace

cv::Mat withImageNoise(const cv::Mat& gray, double sigma, std::uint32_t seed, Timestamp t) {
  // splitmix64 of (seed, t): neighbouring stamps and seeds give unrelated streams.
  std::uint64_t z = (static_cast<std::uint64_t>(seed) << 32) ^ static_cast<std::uint64_t>(t);
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  z ^= z >> 31;
  cv::RNG rng(z | 1);  // cv::RNG treats 0 as a special state
  cv::Mat noise(gray.size(), CV_32F);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
  cv::Mat out;
  gray.convertTo(out, CV_32F);
  out += noise;
  out.convertTo(out, CV_8U);  // rounds to nearest and saturates to 0..255
  return out;
}

std::vector<FrameObservations> framesFromTracks(const Sequence& seq, double sigma,
                                                std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<FrameObservations> frames;
  for (const auto& o : seq.landmark_observations) {
    if (frames.empty() || frames.back().t != o.t) frames.push_back({o.t, {}});
    Vec2 uv(o.u, o.v);
    if (sigma > 0.0) uv += sigma * Vec2(noise(rng), noise(rng));
    frames.back().features.push_back({o.landmark_id, uv});
  }
  // Frames without any observation still carry a time (tracking loss): keep image times.
  for (const auto& img : seq.images) {
    auto it = std::lower_bound(frames.begin(), frames.end(), img.t,
                               [](const FrameObservations& f, Timestamp t) { return f.t < t; });
    if (it == frames.end() || it->t != img.t) frames.insert(it, FrameObservations{img.t, {}});
  }
  return frames;
}

VioRunOutput runVioOnTracks(const Sequence& seq, const VioBackendOptions& options,
                            const VioRunOptions& run,
                            std::shared_ptr<const learned::ResidualForceProvider> residual_force) {
  return runVioOnFrames(seq, framesFromTracks(seq, run.pixel_noise_sigma, run.seed), options, run,
                        std::move(residual_force));
}

VioRunOutput runVioOnFrames(const Sequence& seq, const std::vector<FrameObservations>& frames,
                            const VioBackendOptions& options, const VioRunOptions& run,
                            std::shared_ptr<const learned::ResidualForceProvider> residual_force) {
  if (!seq.camera) throw InputError(seq.source, 0, "sequence has no camera calibration");
  if (seq.imu.empty()) throw InputError(seq.source, 0, "sequence has no IMU data");
  SampleFeeder feeder(seq, checkedThrust(seq, options.method));
  if (frames.empty()) throw InputError(seq.source, 0, "sequence has no landmark tracks or frames");

  VisualEstimator est({options, run, {}}, *seq.camera, std::move(residual_force), groundTruthOf(seq));
  VioRunOutput out;
  const auto start = std::chrono::steady_clock::now();
  for (const auto& frame : frames) {
    feeder.feedUntil(&est, frame.t);
    const bool first = !est.initialized();
    const std::optional<FrameResult> r = est.addTrackedFrame(frame);
    if (!r) continue;
    if (first) recordStart(est.starter(), frame.t, &out);
    out.frames.push_back(*r);
    out.states.push_back(r->state);
  }
  out.backend_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.vi_init_attempts = est.starter().viInitAttempts();
  if (const ViInitResult* r = est.starter().viInitResult()) out.vi_init = *r;
  if (!est.starter().started()) throw InputError(seq.source, 0, est.starter().notStartedReason());
  feeder.feedRest(&est);
  recordModelForces(est, &out);
  return out;
}

ImageRunOutput runVioOnImages(const Sequence& seq, const VioBackendOptions& options,
                              const VioRunOptions& run, const VisualFrontendConfig& config,
                              std::shared_ptr<const learned::ResidualForceProvider> residual_force,
                              bool log, const std::function<void(Timestamp)>& on_image,
                              const std::function<void(const ImageStep&)>& on_step) {
  if (!seq.hasImages())
    throw InputError(seq.source, 0, "sequence has no camera calibration or no cam0 images");
  if (seq.imu.empty()) throw InputError(seq.source, 0, "sequence has no IMU data");
  SampleFeeder feeder(seq, checkedThrust(seq, options.method));
  VisualEstimator est({options, run, config}, *seq.camera, std::move(residual_force),
                      groundTruthOf(seq));

  ImageRunOutput out;
  bool lost = false;
  int lost_run = 0;
  // Decoding runs on one I/O thread ahead of the estimator; load_ms is what this thread waited.
  // Each image is checked against the calibration (size, 8-bit, complete file): exit 2 at the image.
  const CameraCalibration* camera = &*seq.camera;
  const double noise = run.image_noise_sigma;
  const std::uint32_t seed = run.seed;
  io::ImagePrefetcher images(seq.images, 4, [camera, noise, seed](const ImageRef& r) {
    const cv::Mat pixels = io::loadImage(r, camera);
    return noise > 0.0 ? withImageNoise(pixels, noise, seed, r.t) : pixels;
  });
  for (const ImageRef& ref : seq.images) {
    if (on_image) on_image(ref.t);
    feeder.feedUntil(&est, ref.t);
    const double waited_before = images.waitSeconds();
    const cv::Mat pixels = images.take();
    const double load_ms = 1e3 * (images.waitSeconds() - waited_before);
    const int init_images_before = est.initImages();
    ImageStep step = est.addImage(ref.t, pixels);
    // An image the initialization tracker saw counts there.
    const bool load_counted = est.initImages() > init_images_before;
    if (load_counted) out.load_time_s += load_ms * 1e-3;
    if (!step.started) continue;
    if (step.first) {
      recordStart(est.starter(), ref.t, &out.vio);
      if (log) logStart(out.vio, seq.images.front().t);
    }
    ImageFrameRecord& rec = step.record;
    rec.load_ms = load_counted ? 0.0 : load_ms;
    if (on_step) on_step(step);
    out.reinitializations += rec.reinitialized ? 1 : 0;
    out.load_time_s += rec.load_ms * 1e-3;
    out.images.push_back(rec);
    if (step.result) {
      out.vio.frames.push_back(*step.result);
      out.vio.states.push_back(step.result->state);
    }
    if (!rec.used_by_backend && !step.first) {
      ++out.lost_images;
      ++lost_run;
      if (!lost && log)
        std::fprintf(stderr, "\nhdvio_run: frontend lost at t=%.3f s (%s, %d features): "
                             "backend continues on IMU%s\n",
                     toSeconds(ref.t), frontend::toString(rec.stage).c_str(), rec.tracked_features,
                     usesDynamics(options.method) ? " and dynamics" : "");
      lost = true;
    } else if (rec.reinitialized && !lost && !step.first && log) {
      std::fprintf(stderr, "\nhdvio_run: map re-initialized at t=%.3f s (%d features)\n",
                   toSeconds(ref.t), rec.tracked_features);
    } else if (lost) {
      if (log)
        std::fprintf(stderr, "hdvio_run: frontend tracking again at t=%.3f s after %d lost "
                             "images%s\n",
                     toSeconds(ref.t), lost_run, rec.reinitialized ? " (map re-initialized)" : "");
      lost = false;
      lost_run = 0;
    }
  }
  out.vio.backend_time_s = est.backendSeconds();
  out.frontend_time_s = est.frontendSeconds();
  out.init_time_s = est.initSeconds();
  out.init_images = est.initImages();
  if (!est.starter().started()) throw InputError(seq.source, 0, est.starter().notStartedReason());
  if (out.vio.frames.empty())
    throw InputError(seq.source, 0, "no image could be processed (images outside the IMU data?)");
  if (log)
    std::fprintf(stderr, "hdvio_run: frontend saw %zu images, %d lost (IMU-only backend steps), "
                         "%d map re-initializations\n",
                 out.images.size(), out.lost_images, out.reinitializations);
  feeder.feedRest(&est);
  recordModelForces(est, &out.vio);
  return out;
}

}  // namespace hdvio
