#include "track_runner.h"

#include <algorithm>
#include <cstdlib>

#include "hdvio/core/error.h"
#include "hdvio/frontend/gyro_prior.h"
#include "hdvio/io/image.h"

namespace hdvio::frontend {
namespace {

std::optional<Pose> groundTruthAt(const std::vector<GroundTruthState>& gt, Timestamp t) {
  auto it = std::lower_bound(gt.begin(), gt.end(), t,
                             [](const GroundTruthState& s, Timestamp x) { return s.t < x; });
  const GroundTruthState* best = nullptr;
  if (it != gt.end()) best = &*it;
  if (it != gt.begin() && (!best || t - (it - 1)->t < best->t - t)) best = &*(it - 1);
  if (!best || std::llabs(best->t - t) > 5'000'000) return std::nullopt;
  return best->T_WB;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

TrackRunSummary runTracking(const Sequence& seq, const TrackRunOptions& options,
                            const std::function<void(const TrackedFrame&)>& on_frame) {
  if (!seq.hasImages())
    throw InputError(seq.source, 0, "sequence has no camera calibration or no images");
  SemiDirectFrontend frontend(*seq.camera, options.frontend);
  TrackRunSummary summary;
  std::vector<double> times, cpu_times, features;
  const std::size_t n = options.max_frames > 0
                            ? std::min<std::size_t>(options.max_frames, seq.images.size())
                            : seq.images.size();
  for (std::size_t i = 0; i < n; ++i) {
    const ImageRef& ref = seq.images[i];
    ImageFrame frame{ref.t, io::loadImage(ref, &*seq.camera)};
    TrackingPrior prior;
    if (options.gyro_prior && i > 0 && seq.hasImu())
      prior.q_prev_cur = integrateGyro(seq.imu, seq.images[i - 1].t, ref.t);
    TrackedFrame tf;
    tf.groundtruth_T_WB = groundTruthAt(seq.groundtruth, ref.t);
    if (options.groundtruth_bootstrap && frontend.wantsPosePrior() && tf.groundtruth_T_WB) {
      prior.T_WB = tf.groundtruth_T_WB;
      tf.used_groundtruth = true;
    }
    tf.result = frontend.track(frame, prior);
    const FrameResult& r = tf.result;
    summary.tracked += r.tracked;
    summary.lost += !r.tracked;
    summary.reinitializations += r.reinitialized;
    summary.keyframes += r.keyframe.has_value();
    summary.groundtruth_priors += tf.used_groundtruth;
    times.push_back(r.timing.total_ms);
    cpu_times.push_back(r.timing.cpu_ms);
    summary.max_cpu_ms = std::max(summary.max_cpu_ms, r.timing.cpu_ms);
    if (r.tracked && i > 0) features.push_back(r.tracked_features);
    if (on_frame) on_frame(tf);
    summary.frames.push_back(std::move(tf));
  }
  summary.median_ms = median(times);
  summary.median_cpu_ms = median(cpu_times);
  for (double t : times) {
    summary.mean_ms += t / times.size();
    summary.max_ms = std::max(summary.max_ms, t);
  }
  if (!features.empty()) {
    summary.min_features = static_cast<int>(*std::min_element(features.begin(), features.end()));
    summary.median_features = static_cast<int>(median(features));
  }
  return summary;
}

}  // namespace hdvio::frontend
