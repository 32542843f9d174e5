#pragma once
// Feeds a recorded sequence through an InertialEstimator in time order: all of its IMU and the
// given thrust, the filter started at the first sample of `span` from `init` and stopped after
// its last. This is all hdvio_run does with an inertial method besides configuration and
// result writing.
#include <functional>
#include <vector>

#include "hdvio/core/sequence.h"
#include "hdvio/pipeline/inertial_estimator.h"

namespace hdvio {

// span: the IMU samples the filter runs on (a contiguous part of seq.imu); init.t = its first.
// Stage times as imo::runImoFilter's (thread CPU). on_progress (may be empty): after each
// sample of the span.
imo::ImoRunOutput runInertialOnSequence(const Sequence& seq, const std::vector<ThrustSample>& thrust,
                                        const std::vector<ImuSample>& span, const NavState& init,
                                        const InertialEstimatorOptions& options,
                                        const DisplacementSourceFactory& source,
                                        const std::function<void(Timestamp)>& on_progress = {});

}  // namespace hdvio
