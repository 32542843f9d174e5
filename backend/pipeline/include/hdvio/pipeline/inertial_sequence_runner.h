#pragma once
// Feeds a recorded sequence through an InertialEstimator in time order: all of its IMU, the
// given thrust and gate frames (a frame after the IMU and thrust up to its time), the filter
// started at the first sample of `span` from `init` and stopped after its last. This is all
// hdvio_run does with an inertial method besides configuration and result writing.
#include <functional>
#include <vector>

#include "hdvio/core/sequence.h"
#include "hdvio/io/gate_corners.h"
#include "hdvio/pipeline/inertial_estimator.h"

namespace hdvio {

// span: the IMU samples the filter runs on (a contiguous part of seq.imu); init.t = its first.
// frames: only with gate updates (else empty). Stage times: thread CPU time, the propagation
// the whole run's minus the updaters'. on_progress (may be empty): after each sample of the
// span.
imo::ImoRunOutput runInertialOnSequence(const Sequence& seq, const std::vector<ThrustSample>& thrust,
                                        const std::vector<imo::GateFrame>& frames,
                                        const std::vector<ImuSample>& span, const NavState& init,
                                        const InertialEstimatorOptions& options,
                                        const DisplacementSourceFactory& source,
                                        const std::function<void(Timestamp)>& on_progress = {});

// The IMU samples the inertial methods run on: from the first sample inside the ground truth
// (+ start_offset_s), for duration_s (<= 0: to the end). InputError when no sample is inside.
std::vector<ImuSample> imuSpanWithGroundTruth(const Sequence& seq, double start_offset_s,
                                              double duration_s);

// Detections grouped per frame (time order), each corner with its known world position.
std::vector<imo::GateFrame> gateFrames(const io::GateData& data);

}  // namespace hdvio
