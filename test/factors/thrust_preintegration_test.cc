// Hybrid-dynamics preintegration against an analytic flight with an external force, a
// Monte-Carlo covariance (all noise sources) and re-integration.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "hdvio/factors/dynamics_factors.h"
#include "hdvio/factors/thrust_preintegration.h"
#include "test_support.h"

namespace hdvio {
namespace {
using test::AnalyticFlight;

constexpr double kTi = 0.2, kTj = 1.2;
const Vec3 kExternalForce(0.5, -0.3, 0.2);  // world frame, m/s^2

// Body-frame residual force (drag-like) and the thrust that, with it, explains the flight.
Vec3 residualForce(const AnalyticFlight& f, double t) { return -0.2 * f.R(t).transpose() * f.v(t); }
Vec3 thrust(const AnalyticFlight& f, double t) {
  return f.R(t).transpose() * (f.acc(t) - gravityWorld() - kExternalForce) - residualForce(f, t);
}

// IMU at imu_hz, thrust at a quarter of it and offset by a fraction of a period.
PreintegratedThrust integrateFlight(double imu_hz, const Vec6& bias = Vec6::Zero()) {
  const AnalyticFlight f;
  const auto imu = test::sampleImu(f, imu_hz, 1.5);
  std::vector<ThrustSample> th;
  const double thrust_hz = imu_hz / 4.0;
  for (double t = 0.3 / thrust_hz; t < 1.5; t += 1.0 / thrust_hz)
    th.push_back({fromSeconds(t), thrust(f, t)});
  th.insert(th.begin(), {0, thrust(f, 0.0)});
  const ResidualForceFn res = [&f](Timestamp t) { return residualForce(f, toSeconds(t)); };
  return PreintegratedThrust::integrate(imu, th, fromSeconds(kTi), fromSeconds(kTj), bias,
                                        ThrustNoiseParams(), res);
}

Eigen::Vector3d errorsAgainstTruth(const PreintegratedThrust& pit) {
  const AnalyticFlight f;
  const double dt = kTj - kTi;
  const Vec3 g = gravityWorld() + kExternalForce;
  const Mat3 RiT = f.R(kTi).transpose();
  const Vec3 beta = RiT * (f.v(kTj) - f.v(kTi) - g * dt);
  const Vec3 alpha = RiT * (f.p(kTj) - f.p(kTi) - f.v(kTi) * dt - 0.5 * g * dt * dt);
  // gamma / dt is the external force seen in frame i (VID-Fusion's mean).
  const Vec3 force_mean = f.R(kTi) * pit.gamma() / pit.dt();
  return Eigen::Vector3d((pit.alpha() - alpha).norm(), (pit.beta() - beta).norm(),
                         (force_mean - kExternalForce).norm());
}

TEST(ThrustPreintegration, MatchesAnalyticFlightAndConvergesSecondOrder) {
  const Eigen::Vector3d coarse = errorsAgainstTruth(integrateFlight(250.0));
  const Eigen::Vector3d fine = errorsAgainstTruth(integrateFlight(1000.0));
  std::printf("alpha / beta / force-mean errors: 250 Hz %.3g %.3g %.3g, 1000 Hz %.3g %.3g %.3g\n",
              coarse[0], coarse[1], coarse[2], fine[0], fine[1], fine[2]);
  EXPECT_LT(fine[0], 3e-5);  // alpha, m
  EXPECT_LT(fine[1], 5e-5);  // beta, m/s
  EXPECT_LT(fine[2], 5e-5);  // external force mean, m/s^2
  for (int i = 0; i < 3; ++i) EXPECT_GT(coarse[i] / fine[i], 12.0) << "component " << i;
}

TEST(ThrustPreintegration, DynamicsFactorResidualIsSmallAtGroundTruth) {
  const AnalyticFlight f;
  auto pit = std::make_shared<PreintegratedThrust>(integrateFlight(1000.0));
  using namespace symbols;
  Values v;
  v.insertPose(X(0), Pose(f.R(kTi), f.p(kTi)));
  v.insertPose(X(1), Pose(f.R(kTj), f.p(kTj)));
  v.insertVector(V(0), f.v(kTi));
  v.insertVector(V(1), f.v(kTj));
  v.insertVector(F(0), kExternalForce);
  v.insertVector(F(1), kExternalForce);
  v.insertVector(B(0), Eigen::VectorXd::Zero(6));
  DynamicsFactorParams params;
  params.force_prior_sigma = 0.1;
  const HdvioDynamicsFactor hdvio(X(0), V(0), F(0), X(1), V(1), F(1), B(0), pit, params);
  const VidDynamicsFactor vid(X(0), V(0), F(0), X(1), V(1), B(0), pit, params);
  for (const Factor* factor : {static_cast<const Factor*>(&hdvio), static_cast<const Factor*>(&vid)}) {
    Eigen::VectorXd r;
    ASSERT_TRUE(factor->whitenedError(v, &r));
    EXPECT_LT(r.cwiseAbs().maxCoeff(), 0.05) << r.transpose();
  }
  // A wrong external force is visible in the (alpha, beta) part, for hdvio where the walk lets
  // the force move little inside the 1-s interval.
  params.force_random_walk = 0.01;
  const HdvioDynamicsFactor tight(X(0), V(0), F(0), X(1), V(1), F(1), B(0), pit, params);
  v.update(F(0), kExternalForce + Vec3(0.3, 0.0, 0.0));
  Eigen::VectorXd r;
  ASSERT_TRUE(tight.whitenedError(v, &r));
  EXPECT_GT(r.head<6>().cwiseAbs().maxCoeff(), 1.0);
}

TEST(ThrustPreintegration, CovarianceMatchesMonteCarlo) {
  const AnalyticFlight f;
  std::vector<DynamicsStep> steps;
  for (int k = 0; k < 200; ++k) {
    const double t = kTi + (k + 0.5) * 0.005;
    DynamicsStep s;
    s.dt = 0.005;
    s.gyro = f.gyro(t);
    s.thrust = thrust(f, t);
    s.residual_force = residualForce(f, t);
    steps.push_back(s);
  }
  ThrustNoiseParams params;
  params.gyro_noise_density = 5e-3;
  params.gyro_random_walk = 2e-2;
  params.thrust_noise_density = Vec3(0.05, 0.08, 0.12);
  params.thrust_direction_noise_density = 0.005;  // 0.07 rad per 5 ms sample: linear regime
  params.residual_force_noise_density = Vec3(0.03, 0.03, 0.03);
  const auto nominal = PreintegratedThrust::integrate(steps, Vec6::Zero(), params);

  constexpr int kRuns = 2000;
  std::mt19937 rng(8);
  std::normal_distribution<double> n(0.0, 1.0);
  auto noise = [&](double sigma) { return Vec3(sigma * n(rng), sigma * n(rng), sigma * n(rng)); };
  Eigen::MatrixXd errors(9, kRuns);
  for (int run = 0; run < kRuns; ++run) {
    ThrustPreintegrator p(Vec6::Zero(), params, /*keep_steps=*/false);
    Vec3 bias_drift = Vec3::Zero();
    for (DynamicsStep s : steps) {
      const double isd = 1.0 / std::sqrt(s.dt);
      s.gyro += bias_drift + noise(params.gyro_noise_density * isd);
      s.thrust = quatExp(noise(params.thrust_direction_noise_density * isd)) * s.thrust;
      s.thrust += params.thrust_noise_density.cwiseProduct(noise(isd));
      s.residual_force += params.residual_force_noise_density.cwiseProduct(noise(isd));
      p.add(s);
      bias_drift += noise(params.gyro_random_walk * std::sqrt(s.dt));
    }
    const PreintegratedThrust noisy = p.finish();
    errors.col(run) << so3Log(nominal.deltaR().transpose() * noisy.deltaR()),
        noisy.beta() - nominal.beta(), noisy.alpha() - nominal.alpha();
  }
  const Eigen::VectorXd mean = errors.rowwise().mean();
  const Eigen::MatrixXd centered = errors.colwise() - mean;
  const Mat9 sample_cov = centered * centered.transpose() / (kRuns - 1);
  double worst = 0.0;
  for (int d = 0; d < 9; ++d) worst = std::max(worst, std::abs(sample_cov(d, d) / nominal.covariance()(d, d) - 1.0));
  std::printf("thrust Monte-Carlo (2000 runs): largest diagonal deviation %.1f %%\n", 100.0 * worst);
  for (int d = 0; d < 9; ++d)
    EXPECT_NEAR(sample_cov(d, d) / nominal.covariance()(d, d), 1.0, 0.10) << "diagonal entry " << d;
  // The (alpha, beta) block used by the factor is the same numbers, reordered.
  const auto ab = nominal.alphaBetaCovariance();
  EXPECT_DOUBLE_EQ(ab(0, 0), nominal.covariance()(6, 6));
  EXPECT_DOUBLE_EQ(ab(3, 3), nominal.covariance()(3, 3));
  EXPECT_DOUBLE_EQ(ab(0, 3), nominal.covariance()(6, 3));
}

TEST(ThrustPreintegration, BiasCorrectionMatchesReintegration) {
  Vec6 b0;
  b0 << 0.01, -0.02, 0.015, 0.1, -0.05, 0.2;
  const PreintegratedThrust pit = integrateFlight(400.0, b0);
  auto errors = [&](double scale) {
    Vec6 db;
    db << 0.01, 0.008, -0.012, 0.05, -0.08, 0.06;
    const Vec6 b = b0 + scale * db;
    const PreintegratedThrust re = pit.reintegrated(b);
    const Vec3 bg = b.head<3>();
    Eigen::Vector3d corrected((re.alpha() - pit.correctedAlpha(bg)).norm(),
                              (re.beta() - pit.correctedBeta(bg)).norm(),
                              (re.gamma() - pit.correctedGamma(b)).norm());
    Eigen::Vector3d uncorrected((re.alpha() - pit.alpha()).norm(), (re.beta() - pit.beta()).norm(),
                                (re.gamma() - pit.gamma()).norm());
    return std::make_pair(corrected, uncorrected);
  };
  const auto [corr1, uncorr1] = errors(1.0);
  const auto [corr2, uncorr2] = errors(0.5);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(corr1[i], 0.02 * uncorr1[i]) << "component " << i;
    EXPECT_NEAR(corr2[i] / corr1[i], 0.25, 0.05) << "component " << i;
  }
}

}  // namespace
}  // namespace hdvio
