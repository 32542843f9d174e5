#include "hdvio/pipeline/inertial_sequence_runner.h"

#include <stdexcept>
#include <utility>

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

}  // namespace hdvio
