#include "hdvio/pipeline/inertial_sequence_runner.h"

#include <stdexcept>
#include <utility>

#include "hdvio/backend/imo/imo_run_support.h"
#include "hdvio/core/thread_clock.h"

namespace hdvio {

imo::ImoRunOutput runInertialOnSequence(const Sequence& seq, const std::vector<ThrustSample>& thrust,
                                        const std::vector<ImuSample>& span, const NavState& init,
                                        const InertialEstimatorOptions& options,
                                        const DisplacementSourceFactory& source,
                                        const std::function<void(Timestamp)>& on_progress) {
  if (span.empty() || span.front().t != init.t)
    throw std::invalid_argument("IMO run: the initial time is not an IMU sample time");
  InertialEstimator est(options, source);
  est.stopAfter(span.back().t);
  const double t_run = threadCpuSeconds();
  std::size_t j = 0;  // thrust up to each IMU sample's time first
  for (const ImuSample& s : seq.imu) {
    while (j < thrust.size() && thrust[j].t <= s.t) est.addThrust(thrust[j++]);
    est.addImu(s);
    if (s.t == init.t) est.initialize(init);
    if (on_progress && est.initialized() && s.t > init.t && s.t <= span.back().t) on_progress(s.t);
  }
  while (j < thrust.size()) est.addThrust(thrust[j++]);
  if (!est.initialized()) throw std::invalid_argument("IMO run: the initial time is not an IMU sample time");
  est.finish();
  imo::ImoRunOutput out = std::move(est.output());
  const double total = threadCpuSeconds() - t_run;
  if (options.network_only) {
    out.propagation_s = total - out.source_s;  // with concatenation and output
  } else {
    out.propagation_s = total - est.gridSeconds();  // with the per-sample state output
    out.update_s = est.gridSeconds() - out.source_s;
  }
  return out;
}

}  // namespace hdvio
