#include "hdvio/pipeline/inertial_sequence_runner.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "hdvio/core/error.h"
#include "hdvio/core/thread_clock.h"

namespace hdvio {

imo::ImoRunOutput runInertialOnSequence(const Sequence& seq, const std::vector<ThrustSample>& thrust,
                                        const std::vector<imo::GateFrame>& frames,
                                        const std::vector<ImuSample>& span, const NavState& init,
                                        const InertialEstimatorOptions& options,
                                        const DisplacementSourceFactory& source,
                                        const std::function<void(Timestamp)>& on_progress) {
  if (span.empty() || span.front().t != init.t)
    throw std::invalid_argument("IMO run: the initial time is not an IMU sample time");
  InertialEstimator est(options, source);
  est.stopAfter(span.back().t);
  const double t_run = threadCpuSeconds();
  std::size_t j = 0, f = 0;  // thrust and frames up to each IMU sample's time first
  for (const ImuSample& s : seq.imu) {
    while (j < thrust.size() && thrust[j].t <= s.t) est.addThrust(thrust[j++]);
    while (f < frames.size() && frames[f].t < s.t) est.addFrame(frames[f++]);
    est.addImu(s);
    if (s.t == init.t) est.initialize(init);
    if (on_progress && est.initialized() && s.t > init.t && s.t <= span.back().t) on_progress(s.t);
  }
  while (j < thrust.size()) est.addThrust(thrust[j++]);
  while (f < frames.size()) est.addFrame(frames[f++]);
  if (!est.initialized()) throw std::invalid_argument("IMO run: the initial time is not an IMU sample time");
  est.finish();
  imo::ImoRunOutput out = std::move(est.output());
  // with the per-sample state output
  out.propagation_s = threadCpuSeconds() - t_run - out.source_s - out.update_s - out.gate_update_s;
  return out;
}

std::vector<imo::GateFrame> gateFrames(const io::GateData& data) {
  std::vector<imo::GateFrame> frames;
  for (const io::GateCornerDetection& d : data.detections) {
    if (frames.empty() || frames.back().t != d.t) frames.push_back({d.t, {}});
    frames.back().corners.push_back({data.corners.at({d.gate_id, d.corner_id}), Vec2(d.u, d.v)});
  }
  return frames;
}

std::vector<ImuSample> imuSpanWithGroundTruth(const Sequence& seq, double start_offset_s,
                                              double duration_s) {
  if (seq.groundtruth.empty()) throw InputError(seq.source, 0, "the sequence has no ground truth");
  const Timestamp t_gt = seq.groundtruth.front().t + fromSeconds(start_offset_s);
  auto first = std::lower_bound(seq.imu.begin(), seq.imu.end(), t_gt,
                                [](const ImuSample& s, Timestamp t) { return s.t < t; });
  if (first == seq.imu.end() || first->t > seq.groundtruth.back().t)
    throw InputError(seq.source, 0, "no IMU sample inside the ground-truth span");
  auto last = seq.imu.end();
  if (duration_s > 0.0)
    last = std::upper_bound(first, seq.imu.end(), first->t + fromSeconds(duration_s),
                            [](Timestamp t, const ImuSample& s) { return t < s.t; });
  return std::vector<ImuSample>(first, last);
}

}  // namespace hdvio
