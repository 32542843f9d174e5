// The IMO filter family on the real IMU of the Blackbird validation flight: the filter with
// true displacements tracks the ground truth, and the streaming InertialEstimator (IMU and
// thrust fed sample by sample, the thrust 30 ms late; windows wait for the thrust up to their
// end) gives exactly the states of the run whose source sees the whole flight at once (what
// hdvio_run does, runInertialOnSequence) for the Model-EKF and the shipped imo network.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "../common/blackbird_val.h"
#include "hdvio/backend/imo/drag_model.h"
#include "hdvio/io/sequence_reader.h"
#include "hdvio/pipeline/displacement_network_source.h"
#include "hdvio/pipeline/inertial_estimator.h"
#include "hdvio/pipeline/inertial_sequence_runner.h"

namespace hdvio {
namespace {

using test::blackbirdVal;
using test::kBlackbirdVal;
using test::positionRmse;

// The IMU samples from the first with ground truth, for duration_s.
std::vector<ImuSample> span(const Sequence& seq, double duration_s) {
  std::vector<ImuSample> imu;
  for (const auto& s : seq.imu)
    if (s.t >= seq.groundtruth.front().t && s.t <= seq.groundtruth.front().t + fromSeconds(duration_s))
      imu.push_back(s);
  return imu;
}

// The flight through runInertialOnSequence with a source over all of its data (the whole
// flight at once): the reference the streamed runs must equal.
imo::ImoRunOutput wholeFlight(const Sequence& seq, const std::vector<ThrustSample>& thrust,
                              const std::vector<ImuSample>& imu, const NavState& init,
                              const InertialEstimatorOptions& options, const imo::DisplacementSource& source) {
  return runInertialOnSequence(seq, thrust, {}, imu, init, options,
                               [source](const InertialBuffers&) { return source; });
}

// The filter on the real IMU of the Blackbird validation flight, updated with ground-truth
// displacements (0.01 m sigma): real sensor timing, biases and rates, a measurement we trust.
TEST(ImoFilterRun, FilterOnRealImuWithTrueDisplacementsTracksGroundTruth) {
  if (!std::filesystem::exists(kBlackbirdVal)) GTEST_SKIP() << "no " << kBlackbirdVal;
  const Sequence& seq = blackbirdVal();
  std::vector<ImuSample> imu;
  for (const auto& s : seq.imu)
    if (s.t >= seq.groundtruth.front().t && s.t <= seq.groundtruth.front().t + fromSeconds(15.0))
      imu.push_back(s);
  NavState init = groundTruthState(seq, imu.front().t);
  init.bias.setZero();
  const imo::DisplacementSource truth = [&seq](const imo::DisplacementRequest& r)
      -> std::optional<imo::DisplacementEstimate> {
    return imo::DisplacementEstimate{groundTruthState(seq, r.t_end).T_WB.p -
                                         groundTruthState(seq, r.t_begin).T_WB.p,
                                     Mat3::Identity()};
  };
  const imo::ImoRunOutput out = wholeFlight(seq, {}, imu, init, InertialEstimatorOptions{}, truth);
  const imo::ImoRunOutput dead = wholeFlight(seq, {}, imu, init, InertialEstimatorOptions{},
                                             [](const imo::DisplacementRequest&) { return std::nullopt; });
  double max_err = 0.0, max_dead = 0.0;
  const double rmse = positionRmse(seq, out.states, &max_err);
  positionRmse(seq, dead.states, &max_dead);
  EXPECT_NEAR(out.updates, 290, 1);  // 20 Hz over 15 s, from 0.5 s on
  EXPECT_LT(rmse, 0.05) << "max " << max_err;
  EXPECT_LT(max_err, 0.15);
  EXPECT_GT(max_dead, 10.0);  // the same IMU without updates
  double max_rot = 0.0;
  for (const NavState& s : out.states)
    max_rot = std::max(max_rot, so3Log(groundTruthState(seq, s.t).T_WB.R().transpose() *
                                       s.T_WB.R()).norm());
  EXPECT_LT(max_rot * 180.0 / M_PI, 5.0);
}

// Feeds the whole sequence as a live program would, with the thrust arriving 30 ms late (a
// rotor-speed message behind the IMU): before each IMU sample the thrust up to 30 ms before it;
// the filter starts at the span's first sample and stops after its last.
std::vector<NavState> streamed(const Sequence& seq, const std::vector<ThrustSample>& thrust,
                               const std::vector<ImuSample>& imu, const NavState& init,
                               const InertialEstimatorOptions& options,
                               const DisplacementSourceFactory& source, imo::ImoRunOutput* counts) {
  InertialEstimator est(options, source);
  est.stopAfter(imu.back().t);
  std::size_t j = 0;
  const Timestamp latency = fromSeconds(0.03);
  for (const ImuSample& s : seq.imu) {
    while (j < thrust.size() && thrust[j].t <= s.t - latency) est.addThrust(thrust[j++]);
    est.addImu(s);
    if (s.t == init.t) est.initialize(init);
  }
  while (j < thrust.size()) est.addThrust(thrust[j++]);
  est.finish();
  *counts = est.output();
  return est.output().states;
}

void expectSameStates(const std::vector<NavState>& a, const std::vector<NavState>& b) {
  ASSERT_EQ(a.size(), b.size());
  int differing = 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].t != b[k].t || a[k].T_WB.p != b[k].T_WB.p || a[k].T_WB.q.coeffs() != b[k].T_WB.q.coeffs() ||
        a[k].v_W != b[k].v_W || a[k].bias != b[k].bias)
      ++differing;
  EXPECT_EQ(differing, 0) << "of " << a.size() << " states";
}

TEST(InertialStreaming, ModelEkfFedSampleBySampleEqualsTheWholeFlightRun) {
  if (!std::filesystem::exists(kBlackbirdVal)) GTEST_SKIP() << "no " << kBlackbirdVal;
  const Sequence& seq = blackbirdVal();
  const std::vector<ThrustSample> thrust = thrustSamples(seq);
  ASSERT_FALSE(thrust.empty());
  const std::vector<ImuSample> imu = span(seq, 20.0);
  const NavState init = groundTruthState(seq, imu.front().t);
  imo::DragModel drag;  // thrust and a plausible linear drag: any model shows the equality
  drag.drag.linear = Vec3(0.3, 0.3, 0.1);
  InertialEstimatorOptions options;
  options.source_needs_thrust = true;
  const Vec3 sigma = options.run.measurement_sigma;
  const Vec3 g = options.run.filter.gravity;
  const imo::ImoRunOutput whole = wholeFlight(
      seq, thrust, imu, init, options, imo::makeDragModelSource(thrust, drag, 0.005, sigma, g, true));
  imo::ImoRunOutput counts;
  const std::vector<NavState> states = streamed(
      seq, thrust, imu, init, options,
      [&](const InertialBuffers& b) { return imo::makeDragModelSource(b.thrust, drag, 0.005, sigma, g, true); },
      &counts);
  EXPECT_GE(whole.updates, 350);  // 20 Hz over 20 s, from 0.5 s on
  EXPECT_EQ(counts.updates, whole.updates);
  EXPECT_EQ(counts.no_measurement, whole.no_measurement);
  expectSameStates(states, whole.states);
}

TEST(InertialStreaming, ImoNetworkAndNetworkOnlyFedSampleBySampleEqualTheWholeFlightRun) {
  if (!std::filesystem::exists(kBlackbirdVal)) GTEST_SKIP() << "no " << kBlackbirdVal;
  const Sequence& seq = blackbirdVal();
  const std::vector<ThrustSample> thrust = thrustSamples(seq);
  const auto model = std::make_shared<const learned::DisplacementModel>(learned::DisplacementModel::load(
      std::string(HDVIO_SOURCE_DIR) + "/learned/models/imo_blackbird.tcn"));
  ASSERT_EQ(model->inputKind(), learned::DisplacementInputKind::kThrustGyro);
  const std::vector<ImuSample> imu = span(seq, 8.0);
  const NavState init = groundTruthState(seq, imu.front().t);
  for (const bool network_only : {false, true}) {
    SCOPED_TRACE(network_only ? "net_only" : "imo");
    InertialEstimatorOptions options;
    options.run.window_s = model->windowSeconds();
    options.run.use_source_covariance = model->hasCovariance();
    options.displacement = network_only ? DisplacementUse::kConcatenate : DisplacementUse::kFilterUpdate;
    options.source_needs_thrust = true;
    const imo::DisplacementSource whole_source = networkDisplacementSource(
        model, std::make_shared<const std::vector<ImuSample>>(seq.imu),
        std::make_shared<const std::vector<ThrustSample>>(thrust));
    const imo::ImoRunOutput whole = wholeFlight(seq, thrust, imu, init, options, whole_source);
    imo::ImoRunOutput counts;
    const std::vector<NavState> states = streamed(
        seq, thrust, imu, init, options,
        [&](const InertialBuffers& b) { return networkDisplacementSource(model, b.imu, b.thrust); },
        &counts);
    EXPECT_GE(whole.updates, 100);
    EXPECT_EQ(counts.updates, whole.updates);
    expectSameStates(states, whole.states);
  }
}

}  // namespace
}  // namespace hdvio
