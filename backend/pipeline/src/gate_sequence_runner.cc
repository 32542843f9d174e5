#include "hdvio/pipeline/gate_sequence_runner.h"

#include <stdexcept>
#include <utility>

namespace hdvio {

imo::GateIoOutput runGateIoOnSequence(const Sequence& seq, const std::vector<ThrustSample>& thrust,
                                      const std::vector<imo::GateFrame>& frames,
                                      const std::vector<ImuSample>& span, const NavState& init,
                                      const GateEstimatorOptions& options, const CameraModel& camera,
                                      const Pose& T_BC, const DisplacementSourceFactory& source,
                                      const std::function<void(Timestamp)>& on_progress) {
  if (span.empty() || span.front().t != init.t)
    throw std::invalid_argument("gate_io: the initial time is not an IMU sample time");
  GateEstimator est(options, camera, T_BC, source);
  est.stopAfter(span.back().t);
  std::size_t j = 0, f = 0;
  for (const ImuSample& s : seq.imu) {
    while (j < thrust.size() && thrust[j].t <= s.t) est.addThrust(thrust[j++]);
    while (f < frames.size() && frames[f].t < s.t) est.addFrame(frames[f++]);
    est.addImu(s);
    if (s.t == init.t) est.initialize(init);
    if (on_progress && est.initialized() && s.t > init.t && s.t <= span.back().t) on_progress(s.t);
  }
  while (j < thrust.size()) est.addThrust(thrust[j++]);
  while (f < frames.size()) est.addFrame(frames[f++]);
  if (!est.initialized()) throw std::invalid_argument("gate_io: the initial time is not an IMU sample time");
  est.finish();
  return std::move(est.output());
}

}  // namespace hdvio
