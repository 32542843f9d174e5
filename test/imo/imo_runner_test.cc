// The IMO run loop on an analytic flight, through the pipeline's InertialEstimator (the
// ImoStepper with its displacement updaters): clone/update schedule, the filter with exact
// displacements correcting a noisy biased IMU, network-only (the model source: drag_model_test).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "analytic_trajectory.h"
#include "hdvio/pipeline/inertial_sequence_runner.h"

namespace hdvio::imo {
namespace {

using testing::simulateImu;
using testing::trajectoryAt;

NavState exactNavState(Timestamp t) {
  const auto s = trajectoryAt(toSeconds(t));
  NavState x;
  x.t = t;
  x.T_WB = Pose(s.R, s.p);
  x.v_W = s.v;
  return x;
}

// Exact displacement p(t_end) - p(t_begin) plus optional noise (fixed seed).
DisplacementSource groundTruthSource(double sigma, std::vector<DisplacementRequest>* log = nullptr) {
  auto rng = std::make_shared<std::mt19937>(11);
  return [sigma, rng, log](const DisplacementRequest& r) -> std::optional<DisplacementEstimate> {
    if (log) log->push_back(r);
    std::normal_distribution<double> n(0.0, sigma);
    const Vec3 d = trajectoryAt(toSeconds(r.t_end)).p - trajectoryAt(toSeconds(r.t_begin)).p;
    return DisplacementEstimate{d + Vec3(n(*rng), n(*rng), n(*rng)),
                                Mat3::Identity() * sigma * sigma};
  };
}

// The flight's IMU fed through an InertialEstimator from init (at the first sample).
ImoRunOutput runImu(const std::vector<ImuSample>& imu, const NavState& init, const ImoRunOptions& run,
                    const DisplacementSource& source,
                    DisplacementUse use = DisplacementUse::kFilterUpdate) {
  Sequence seq;
  seq.imu = imu;
  InertialEstimatorOptions options;
  options.run = run;
  options.displacement = use;
  return runInertialOnSequence(seq, {}, {}, imu, init, options,
                               [source](const InertialBuffers&) { return source; });
}

double positionError(const NavState& s) {
  return (s.T_WB.p - trajectoryAt(toSeconds(s.t)).p).norm();
}

TEST(ImoRunner, UpdatesBetweenClonesOneWindowApartOnTheGrid) {
  const auto imu = simulateImu(100.0, 3.0);
  std::vector<DisplacementRequest> log;
  double max_rotation_error = 0.0;  // world_from_body is only valid during the call
  const DisplacementSource exact = groundTruthSource(0.0, &log);
  const DisplacementSource source = [&](const DisplacementRequest& r) {
    for (double f : {0.0, 0.3, 0.7, 1.0}) {
      const Timestamp t = r.t_begin + static_cast<Timestamp>(f * (r.t_end - r.t_begin));
      const Mat3 R_true = trajectoryAt(toSeconds(t)).R;
      max_rotation_error = std::max(
          max_rotation_error,
          so3Log(R_true.transpose() * r.world_from_body(t).toRotationMatrix()).norm());
    }
    return exact(r);
  };
  const ImoRunOutput out = runImu(imu, exactNavState(0), ImoRunOptions{}, source);
  // Grid 0.05 s, first update once 0.5 s of clones exist: t_end = 0.5 .. 3.0.
  ASSERT_EQ(log.size(), 51u);
  EXPECT_EQ(out.updates, 51);
  for (std::size_t k = 0; k < log.size(); ++k) {
    EXPECT_EQ(log[k].t_end, fromSeconds(0.5) + static_cast<Timestamp>(k) * fromSeconds(0.05));
    EXPECT_EQ(log[k].t_end - log[k].t_begin, fromSeconds(0.5));
  }
  // The orientation handed to the source is the filter's attitude (here: nearly exact).
  EXPECT_LT(max_rotation_error, 1e-3);
  EXPECT_EQ(out.states.size(), imu.size());
}

// filter.release_propagation (scekf.propagate of the IMO release). Level, gravity-cancelling
// accelerometer with a ramp in x, a_k = 0.1 k m/s^2 at t_k = k dt: the two samples' mean
// integrates v_x = 0.1 dt N^2 / 2 over N steps, the sample hold 0.1 dt N (N + 1) / 2.
TEST(ImoRunner, ReleasePropagationHoldsTheNewerSampleAndTheStartAttitude) {
  const double dt = 0.01;
  const int n = 40;
  std::vector<ImuSample> imu;
  for (int k = 0; k <= n; ++k) imu.push_back({fromSeconds(k * dt), Vec3::Zero(), Vec3(0.1 * k, 0.0, 9.81)});
  NavState init;
  init.t = 0;
  init.T_WB = Pose(Mat3::Identity(), Vec3::Zero());
  init.v_W = Vec3::Zero();
  const DisplacementSource none = [](const DisplacementRequest&) { return std::optional<DisplacementEstimate>(); };
  ImoRunOptions o;
  const double v_mid = runImu(imu, init, o, none).states.back().v_W.x();
  o.filter.release_propagation = true;
  const double v_hold = runImu(imu, init, o, none).states.back().v_W.x();
  EXPECT_NEAR(v_mid, 0.1 * dt * n * n / 2.0, 1e-9);
  EXPECT_NEAR(v_hold, 0.1 * dt * n * (n + 1) / 2.0, 1e-9);

  // Constant yaw rate 1 rad/s, body specific force (1, 0, g): the release's first-order step
  // rotates it with the step's start attitude, v_x = sum_k cos(k dt) dt; the default step with
  // the mid-step attitude, sum_k cos((k + 1/2) dt) dt.
  for (auto& s : imu) {
    s.gyro = Vec3(0.0, 0.0, 1.0);
    s.accel = Vec3(1.0, 0.0, 9.81);
  }
  double v_start = 0.0, v_midstep = 0.0;
  for (int k = 0; k < n; ++k) {
    v_start += std::cos(k * dt) * dt;
    v_midstep += std::cos((k + 0.5) * dt) * dt;
  }
  EXPECT_NEAR(runImu(imu, init, o, none).states.back().v_W.x(), v_start, 1e-9);
  o.filter.release_propagation = false;
  EXPECT_NEAR(runImu(imu, init, o, none).states.back().v_W.x(), v_midstep, 1e-9);
  EXPECT_GT(std::abs(v_start - v_midstep), 1e-4);
}

// initial_window_biases: the window's biases stay the initial ones while updates move the
// filter's estimate (which the default hands to the source).
TEST(ImoRunner, InitialWindowBiasesStayFixed) {
  const auto imu = simulateImu(100.0, 2.0);
  NavState init = exactNavState(0);
  init.bias << 0.01, -0.02, 0.005, 0.1, 0.0, -0.1;
  for (bool fixed : {false, true}) {
    std::vector<DisplacementRequest> log;
    ImoRunOptions o;
    o.initial_window_biases = fixed;
    runImu(imu, init, o, groundTruthSource(0.01, &log));
    ASSERT_GT(log.size(), 10u);
    double moved = 0.0;
    for (const auto& r : log)
      moved = std::max(moved, (r.gyro_bias - init.bias.head<3>()).norm() + (r.accel_bias - init.bias.tail<3>()).norm());
    if (fixed) EXPECT_EQ(moved, 0.0);
    else EXPECT_GT(moved, 1e-6);
  }
}

TEST(ImoRunner, ExactDisplacementsCorrectNoisyBiasedImu) {
  auto imu = simulateImu(400.0, 20.0);
  const Vec3 ba(0.2, -0.15, 0.1), bg(0.004, -0.003, 0.002);
  const double gyro_density = 1e-3, accel_density = 2e-2;
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  const double sg = gyro_density * std::sqrt(400.0), sa = accel_density * std::sqrt(400.0);
  for (auto& s : imu) {
    s.gyro += bg + sg * Vec3(n(rng), n(rng), n(rng));
    s.accel += ba + sa * Vec3(n(rng), n(rng), n(rng));
  }
  ImoRunOptions o;
  o.filter.gyro_noise_density = gyro_density;
  o.filter.accel_noise_density = accel_density;
  o.filter.init_accel_bias_sigma = 0.3;
  o.filter.init_gyro_bias_sigma = 0.01;
  o.filter.init_position_sigma = 0.01;
  o.filter.init_velocity_sigma = 0.01;
  o.filter.init_attitude_sigma = o.filter.init_yaw_sigma = 0.01;

  const ImoRunOutput filtered = runImu(imu, exactNavState(0), o, groundTruthSource(0.01));
  const ImoRunOutput dead_reckoning =
      runImu(imu, exactNavState(0), o, [](const DisplacementRequest&) { return std::nullopt; });
  EXPECT_EQ(dead_reckoning.no_measurement, filtered.updates);
  EXPECT_GT(positionError(dead_reckoning.states.back()), 5.0);
  double max_err = 0.0;
  for (std::size_t k = imu.size() / 2; k < filtered.states.size(); ++k)
    max_err = std::max(max_err, positionError(filtered.states[k]));
  EXPECT_LT(max_err, 0.1);
  const NavState& last = filtered.states.back();
  EXPECT_LT((last.bias.tail<3>() - ba).norm(), 0.08) << last.bias.transpose();
  EXPECT_LT((last.bias.head<3>() - bg).norm(), 2.5e-3) << last.bias.transpose();
}

// The logged innovations: one per update at its grid time; their normalized squares average
// ~3 (1 per axis) when the measurement sigma is the displacement noise, and far more when the
// sigma understates it (what scripts/innovation_stats.py and the sigma calibration of
// scripts/imo_cv.sh rely on).
TEST(ImoRunner, InnovationsAreLoggedAndTheirNisMatchesTheMeasurementNoise) {
  auto imu = simulateImu(400.0, 20.0);
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  const double accel_density = 2e-2, gyro_density = 1e-3;
  for (auto& s : imu) {
    s.gyro += gyro_density * 20.0 * Vec3(n(rng), n(rng), n(rng));
    s.accel += accel_density * 20.0 * Vec3(n(rng), n(rng), n(rng));
  }
  ImoRunOptions o;
  o.filter.gyro_noise_density = gyro_density;
  o.filter.accel_noise_density = accel_density;
  o.filter.init_position_sigma = o.filter.init_velocity_sigma = 0.01;
  o.filter.init_attitude_sigma = o.filter.init_yaw_sigma = 0.01;
  const auto meanNis = [&](double noise, double sigma) {
    o.measurement_sigma = Vec3::Constant(sigma);
    const ImoRunOutput out = runImu(imu, exactNavState(0), o, groundTruthSource(noise));
    EXPECT_EQ(out.innovations.size(), static_cast<std::size_t>(out.updates));
    double sum = 0.0;
    int count = 0;
    for (std::size_t k = 0; k < out.innovations.size(); ++k) {
      const UpdateInnovation& u = out.innovations[k];
      EXPECT_TRUE(u.applied);
      if (k > 0) {
        EXPECT_EQ(u.t - out.innovations[k - 1].t, fromSeconds(0.05));
      }
      const Innovation& in = u.innovation;
      EXPECT_NEAR(in.nis, in.residual.dot(in.covariance.ldlt().solve(in.residual)), 1e-9 * (1.0 + in.nis));
      // S = H P H' + R: the state's uncertainty adds to the measurement's.
      for (int a = 0; a < 3; ++a) EXPECT_GT(in.covariance(a, a), sigma * sigma * (1.0 + 1e-6));
      if (toSeconds(u.t) > 2.0) sum += in.nis, ++count;
    }
    return sum / count;
  };
  const double matched = meanNis(0.02, 0.02);
  EXPECT_GT(matched, 2.0);
  EXPECT_LT(matched, 4.0);
  EXPECT_GT(meanNis(0.02, 0.005), 15.0);  // sigma 4x too small: ~16x the NIS
}

TEST(ImoRunner, NetworkOnlyConcatenatesDisplacements) {
  const auto imu = simulateImu(100.0, 5.0);
  ImoRunOptions o;
  const ImoRunOutput out = runImu(imu, exactNavState(0), o, groundTruthSource(0.0), DisplacementUse::kConcatenate);
  ASSERT_EQ(out.states.size(), 101u);  // t = 0 and the 100 grid times
  EXPECT_EQ(out.updates, 91);
  for (const auto& s : out.states) EXPECT_LT(positionError(s), 1e-2) << toSeconds(s.t);
}

}  // namespace
}  // namespace hdvio::imo
