#pragma once
// Feeds a recorded race through a GateEstimator in time order: all of its IMU, the given thrust
// and gate frames (a frame after the IMU and thrust up to its time), the filter started at the
// first sample of `span` from `init` and stopped after its last. This is all hdvio_run does
// with gate_io besides configuration and result writing.
#include <functional>
#include <vector>

#include "hdvio/core/sequence.h"
#include "hdvio/pipeline/gate_estimator.h"

namespace hdvio {

// span: the IMU samples the filter runs on (a contiguous part of seq.imu); init.t = its first.
// on_progress (may be empty): after each sample of the span.
imo::GateIoOutput runGateIoOnSequence(const Sequence& seq, const std::vector<ThrustSample>& thrust,
                                      const std::vector<imo::GateFrame>& frames,
                                      const std::vector<ImuSample>& span, const NavState& init,
                                      const GateEstimatorOptions& options, const CameraModel& camera,
                                      const Pose& T_BC, const DisplacementSourceFactory& source,
                                      const std::function<void(Timestamp)>& on_progress = {});

}  // namespace hdvio
