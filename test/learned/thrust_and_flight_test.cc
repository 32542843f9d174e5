#include <random>

#include <gtest/gtest.h>

#include "hdvio/core/error.h"
#include "hdvio/learned/flight_samples.h"
#include "hdvio/learned/force_metrics.h"
#include "hdvio/learned/thrust_identification.h"

namespace hdvio::learned {
namespace {

// A synthetic 20 s flight at 400 Hz: rotor speeds vary, the accelerometer measures
// c * sum(w^2) along `axis` minus linear drag on body velocity, plus noise.
Sequence syntheticFlight(double c, const Vec3& axis, const Vec3& drag, double noise) {
  Sequence s;
  s.name = "synthetic";
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, noise);
  for (int k = 0; k < 8000; ++k) {
    const double t = k / 400.0;
    const Timestamp ts = fromSeconds(10.0 + t);
    RotorSample r;
    r.t = ts;
    for (int i = 0; i < 4; ++i) r.speeds[i] = 1000.0 + 150.0 * std::sin(0.7 * t + i) + 80.0 * std::sin(3.1 * t);
    s.rotor.push_back(r);
    GroundTruthState g;
    g.t = ts;
    g.T_WB = Pose(quatExp(Vec3(0.2 * std::sin(0.5 * t), 0.1 * std::cos(0.3 * t), 0.4 * t)),
                  Vec3(3 * std::sin(0.5 * t), 2 * std::cos(0.4 * t), 1.0));
    g.v_W = Vec3(1.5 * std::cos(0.5 * t), -0.8 * std::sin(0.4 * t), 0.0);
    g.has_velocity = true;
    s.groundtruth.push_back(g);
    const Vec3 v_body = g.T_WB.q.conjugate() * g.v_W;
    ImuSample m;
    m.t = ts;
    m.gyro = Vec3(0.1, -0.2, 0.4);
    m.accel = c * r.speeds.squaredNorm() * axis - drag.cwiseProduct(v_body) + Vec3(n(rng), n(rng), n(rng));
    s.imu.push_back(m);
  }
  return s;
}

TEST(ThrustIdentification, RecoversCoefficient) {
  const double c = 2.2e-6;
  const ThrustFit fit = fitThrust(syntheticFlight(c, Vec3::UnitZ(), Vec3::Zero(), 0.3));
  EXPECT_NEAR(fit.c_over_m, c, 2e-3 * c);
  EXPECT_EQ(fit.thrust_axis, Vec3::UnitZ());
  EXPECT_NEAR(fit.rmse_axis, 0.3, 0.03);
  EXPECT_NEAR(fit.thrustCoefficient(0.5), 0.5 * fit.c_over_m, 1e-15);
}

TEST(ThrustIdentification, FlipsAxisForZDownImu) {
  const ThrustFit fit = fitThrust(syntheticFlight(2e-6, -Vec3::UnitZ(), Vec3::Zero(), 0.1));
  EXPECT_NEAR(fit.c_over_m, 2e-6, 1e-8);
  EXPECT_EQ(fit.thrust_axis, -Vec3::UnitZ());
}

TEST(ThrustIdentification, RecoversLinearDrag) {
  const Vec3 drag(0.4, 0.3, 0.1);
  ThrustFitOptions o;
  o.fit_linear_drag = true;
  const ThrustFit fit = fitThrust(syntheticFlight(2e-6, Vec3::UnitZ(), drag, 0.05), o);
  EXPECT_NEAR(fit.c_over_m, 2e-6, 2e-8);
  EXPECT_LT((fit.linear_drag - drag).norm(), 0.02) << fit.linear_drag.transpose();
  const ThrustFit no_drag = fitThrust(syntheticFlight(2e-6, Vec3::UnitZ(), drag, 0.05));
  EXPECT_GT(no_drag.rmse_total, 2.0 * fit.rmse_total);
}

// A cross-validation fold's thrust model comes from its training flights only: two flights
// with different coefficients (and the same clock) fit jointly to a value between them, and
// a fold that leaves one out recovers the other's coefficient.
TEST(ThrustIdentification, JointFitUsesOnlyTheGivenFlights) {
  const double c1 = 2.0e-6, c2 = 2.4e-6;
  const Sequence a = syntheticFlight(c1, Vec3::UnitZ(), Vec3::Zero(), 0.05);
  const Sequence b = syntheticFlight(c2, Vec3::UnitZ(), Vec3::Zero(), 0.05);
  const ThrustFit joint = fitThrustJointly({a, b});
  EXPECT_EQ(joint.samples, a.rotor.size() + b.rotor.size());
  EXPECT_GT(joint.c_over_m, c1 + 0.3 * (c2 - c1));
  EXPECT_LT(joint.c_over_m, c2 - 0.3 * (c2 - c1));
  EXPECT_NEAR(fitThrustJointly({a}).c_over_m, c1, 1e-3 * c1);
  EXPECT_NEAR(fitThrustJointly({b}).c_over_m, c2, 1e-3 * c2);
  // [begin, end) of each flight's rotor samples.
  EXPECT_EQ(fitThrustJointly({a, b}, {}, 0.0, 0.5).samples, a.rotor.size() / 2 + b.rotor.size() / 2);
  EXPECT_THROW(fitThrustJointly({}), InputError);
  EXPECT_THROW(fitThrustJointly({a}, {}, 0.5, 0.5), InputError);
}

TEST(ThrustIdentification, RejectsSequencesWithoutRotors) {
  Sequence s = syntheticFlight(2e-6, Vec3::UnitZ(), Vec3::Zero(), 0.1);
  s.rotor.clear();
  EXPECT_THROW(fitThrust(s), InputError);
}

TEST(FlightSamples, ResamplesOnAUniformGrid) {
  Sequence s = syntheticFlight(2e-6, Vec3::UnitZ(), Vec3::Zero(), 0.0);
  RotorCalibration cal;
  cal.mass = 0.5;
  cal.thrust_coefficient = 1e-6;
  s.rotor_calibration = cal;
  const FlightSamples f = resampleFlight(s);
  EXPECT_EQ(f.size(), 2000u);  // 19.9975 s at 100 Hz
  EXPECT_EQ(f.t[1] - f.t[0], 10000000);
  // Sample 10 coincides with rotor/IMU sample 40.
  EXPECT_LT((f.thrust[10] - thrustFromRotors(cal, s.rotor[40].speeds)).norm(), 1e-9);
  EXPECT_LT((f.force[10] - s.imu[40].accel).norm(), 1e-9);
  EXPECT_LT((f.p_W[10] - s.groundtruth[40].T_WB.p).norm(), 1e-12);
  const FlightSamples part = f.slice(100, 300);
  EXPECT_EQ(part.size(), 200u);
  EXPECT_EQ(part.t.front(), f.t[100]);
  s.rotor_calibration.reset();
  EXPECT_THROW(resampleFlight(s), InputError);
}

TEST(ForceMetrics, SplitsXyAndZ) {
  const std::vector<Vec3> pred{Vec3(1, 0, 0), Vec3(0, 0, 2)};
  const std::vector<Vec3> meas{Vec3::Zero(), Vec3::Zero()};
  const ForceRmse r = forceRmse(pred, meas, 2.0);
  EXPECT_NEAR(r.f, std::sqrt((4.0 + 16.0) / 2.0), 1e-12);
  EXPECT_NEAR(r.f_xy, std::sqrt(4.0 / 2.0), 1e-12);
  EXPECT_NEAR(r.f_z, std::sqrt(16.0 / 2.0), 1e-12);
  EXPECT_THROW(forceRmse(pred, {}, 1.0), std::invalid_argument);
}

TEST(ForceMetrics, SigmaCoverageCountsComponentsWithinOneAndTwoSigma) {
  const std::vector<Vec3> meas{Vec3::Zero(), Vec3::Zero()};
  // errors (0.5, 1.5, 2.5) and (1.0, -3.0, 0.0) at sigma 1: within 1 sigma 0.5, 1.0, 0.0 -> 3 of 6;
  // within 2 sigma additionally 1.5 -> 4 of 6.
  const std::vector<Vec3> pred{Vec3(0.5, 1.5, 2.5), Vec3(1.0, -3.0, 0.0)};
  const std::vector<Vec3> sigma{Vec3::Ones(), Vec3::Ones()};
  const SigmaCoverage c = sigmaCoverage(pred, sigma, meas);
  EXPECT_EQ(c.components, 6u);
  EXPECT_NEAR(c.within_1_sigma, 3.0 / 6.0, 1e-12);
  EXPECT_NEAR(c.within_2_sigma, 4.0 / 6.0, 1e-12);
  // Per-axis sigma: doubling only z's sigma moves 2.5 inside 2 sigma.
  const SigmaCoverage z = sigmaCoverage(pred, {Vec3(1, 1, 2), Vec3(1, 1, 2)}, meas);
  EXPECT_NEAR(z.within_2_sigma, 5.0 / 6.0, 1e-12);
  // Gaussian errors at their true sigma: close to 68.3 % / 95.4 %.
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 0.7);
  std::vector<Vec3> e(20000), s(20000, Vec3::Constant(0.7)), zero(20000, Vec3::Zero());
  for (auto& v : e) v = Vec3(n(rng), n(rng), n(rng));
  const SigmaCoverage g = sigmaCoverage(e, s, zero);
  EXPECT_NEAR(g.within_1_sigma, 0.683, 0.01);
  EXPECT_NEAR(g.within_2_sigma, 0.954, 0.005);
  EXPECT_THROW(sigmaCoverage(pred, {Vec3::Ones(), Vec3::Zero()}, meas), std::invalid_argument);
  // Quantile: |e| / sigma = 0.5, 1.5, 2.5, 1, 3, 0 -> sorted 0, 0.5, 1, 1.5, 2.5, 3; the 50 %
  // quantile is the 3rd value. Sigma 3x too large -> factor ~ 1/3 restores 68.3 %.
  EXPECT_DOUBLE_EQ(sigmaQuantile(pred, sigma, meas, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(sigmaQuantile(pred, sigma, meas, 0.99), 3.0);
  std::vector<Vec3> s3(20000, Vec3::Constant(2.1));
  const double q = sigmaQuantile(e, s3, zero, 0.683);
  EXPECT_NEAR(q, 1.0 / 3.0, 0.01);
  std::vector<Vec3> rescaled(20000, Vec3::Constant(2.1 * q));
  EXPECT_NEAR(sigmaCoverage(e, rescaled, zero).within_1_sigma, 0.683, 0.002);
  EXPECT_THROW(sigmaQuantile(pred, sigma, meas, 1.0), std::invalid_argument);
  EXPECT_THROW(sigmaCoverage(pred, sigma, {}), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio::learned
