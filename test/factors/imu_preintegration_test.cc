// IMU preintegration against an analytic flight, a Monte-Carlo covariance and re-integration.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "hdvio/core/error.h"
#include "hdvio/factors/imu_factor.h"
#include "hdvio/factors/imu_preintegration.h"
#include "test_support.h"

namespace hdvio {
namespace {
using test::AnalyticFlight;

constexpr double kTi = 0.2, kTj = 1.2;

struct DeltaErrors {
  double rot, vel, pos;
};

DeltaErrors errorsAtRate(double rate_hz) {
  const AnalyticFlight f;
  const auto imu = test::sampleImu(f, rate_hz, 1.5);
  const auto pim = PreintegratedImu::integrate(imu, fromSeconds(kTi), fromSeconds(kTj), Vec6::Zero(),
                                               ImuNoiseParams());
  const double dt = kTj - kTi;
  const Vec3 g = gravityWorld();
  const Mat3 RiT = f.R(kTi).transpose();
  const Mat3 dR_true = RiT * f.R(kTj);
  const Vec3 dv_true = RiT * (f.v(kTj) - f.v(kTi) - g * dt);
  const Vec3 dp_true = RiT * (f.p(kTj) - f.p(kTi) - f.v(kTi) * dt - 0.5 * g * dt * dt);
  EXPECT_NEAR(pim.dt(), dt, 1e-12);
  return {so3Log(dR_true.transpose() * pim.deltaR()).norm(), (pim.deltaV() - dv_true).norm(),
          (pim.deltaP() - dp_true).norm()};
}

// Noise-free samples: the deltas converge to the analytic ones at second order in the sample
// period (trapezoid-averaged measurements, acceleration rotated to the middle of each step).
TEST(ImuPreintegration, MatchesAnalyticFlightAndConvergesSecondOrder) {
  const DeltaErrors coarse = errorsAtRate(250.0);
  const DeltaErrors fine = errorsAtRate(1000.0);
  std::printf("250 Hz: rot %.3g rad vel %.3g m/s pos %.3g m; 1000 Hz: rot %.3g vel %.3g pos %.3g\n",
              coarse.rot, coarse.vel, coarse.pos, fine.rot, fine.vel, fine.pos);
  EXPECT_LT(fine.rot, 2e-7);
  EXPECT_LT(fine.vel, 1e-5);
  EXPECT_LT(fine.pos, 5e-6);
  // Four times the rate: errors shrink by about sixteen (at least twelve).
  EXPECT_GT(coarse.rot / fine.rot, 12.0);
  EXPECT_GT(coarse.vel / fine.vel, 12.0);
  EXPECT_GT(coarse.pos / fine.pos, 12.0);
}

TEST(ImuPreintegration, FactorResidualIsSmallAtGroundTruth) {
  const AnalyticFlight f;
  const auto imu = test::sampleImu(f, 1000.0, 1.5);
  auto pim = std::make_shared<PreintegratedImu>(PreintegratedImu::integrate(
      imu, fromSeconds(kTi), fromSeconds(kTj), Vec6::Zero(), ImuNoiseParams()));
  using namespace symbols;
  Values v;
  v.insertPose(X(0), Pose(f.R(kTi), f.p(kTi)));
  v.insertPose(X(1), Pose(f.R(kTj), f.p(kTj)));
  v.insertVector(V(0), f.v(kTi));
  v.insertVector(V(1), f.v(kTj));
  v.insertVector(B(0), Eigen::VectorXd::Zero(6));
  v.insertVector(B(1), Eigen::VectorXd::Zero(6));
  ImuFactor factor(X(0), V(0), B(0), X(1), V(1), B(1), pim);
  // Discretization error only (see above), far below one sigma of the default noise.
  Eigen::VectorXd r;
  ASSERT_TRUE(factor.whitenedError(v, &r));
  EXPECT_LT(r.cwiseAbs().maxCoeff(), 0.05) << r.transpose();
}

// Monte-Carlo: perturb every step with white noise of the configured densities and compare the
// spread of [dtheta, dv, dp] with the propagated covariance (diagonal within 10 %).
TEST(ImuPreintegration, CovarianceMatchesMonteCarlo) {
  const AnalyticFlight f;
  const auto imu = test::sampleImu(f, 200.0, 1.5);
  const std::vector<ImuStep> steps = imuSteps(imu, fromSeconds(kTi), fromSeconds(kTj));
  ImuNoiseParams params;
  params.gyro_noise_density = 5e-3;
  params.accel_noise_density = 5e-2;
  const auto nominal = PreintegratedImu::integrate(steps, Vec6::Zero(), params);

  constexpr int kRuns = 2000;
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::MatrixXd errors(9, kRuns);
  for (int run = 0; run < kRuns; ++run) {
    ImuPreintegrator p(Vec6::Zero(), params, /*keep_steps=*/false);
    for (const ImuStep& s : steps) {
      const double sg = params.gyro_noise_density / std::sqrt(s.dt);
      const double sa = params.accel_noise_density / std::sqrt(s.dt);
      p.add(s.gyro + sg * Vec3(n(rng), n(rng), n(rng)), s.accel + sa * Vec3(n(rng), n(rng), n(rng)), s.dt);
    }
    const PreintegratedImu noisy = p.finish();
    errors.col(run) << so3Log(nominal.deltaR().transpose() * noisy.deltaR()),
        noisy.deltaV() - nominal.deltaV(), noisy.deltaP() - nominal.deltaP();
  }
  const Eigen::VectorXd mean = errors.rowwise().mean();
  const Eigen::MatrixXd centered = errors.colwise() - mean;
  const Mat9 sample_cov = centered * centered.transpose() / (kRuns - 1);
  double worst = 0.0;
  for (int d = 0; d < 9; ++d) worst = std::max(worst, std::abs(sample_cov(d, d) / nominal.covariance()(d, d) - 1.0));
  std::printf("IMU Monte-Carlo (2000 runs): largest diagonal deviation %.1f %%\n", 100.0 * worst);
  for (int d = 0; d < 9; ++d) {
    const double predicted = nominal.covariance()(d, d);
    EXPECT_NEAR(sample_cov(d, d) / predicted, 1.0, 0.10) << "diagonal entry " << d;
  }
  // The strongest cross-correlation (v-p along each axis) is reproduced as well.
  for (int a = 0; a < 3; ++a) {
    const double predicted = nominal.covariance()(3 + a, 6 + a);
    EXPECT_NEAR(sample_cov(3 + a, 6 + a) / predicted, 1.0, 0.10) << "v-p axis " << a;
  }
}

// First-order bias correction against full re-integration: the remaining error is second
// order in the bias change (halving the change quarters it) and far below the uncorrected one.
TEST(ImuPreintegration, BiasCorrectionMatchesReintegration) {
  const AnalyticFlight f;
  const auto imu = test::sampleImu(f, 400.0, 1.5);
  Vec6 b0;
  b0 << 0.01, -0.02, 0.015, 0.1, -0.05, 0.2;
  const auto pim = PreintegratedImu::integrate(imu, fromSeconds(kTi), fromSeconds(kTj), b0, ImuNoiseParams());
  ASSERT_EQ(pim.numSteps(), 400u);
  auto errors = [&](double scale) {
    Vec6 db;
    db << 0.01, 0.008, -0.012, 0.05, -0.08, 0.06;
    const Vec6 b = b0 + scale * db;
    const PreintegratedImu re = pim.reintegrated(b);
    EXPECT_EQ(re.bias(), b);
    Eigen::Vector3d corrected(so3Log(re.deltaR().transpose() * pim.correctedDeltaR(b)).norm(),
                              (re.deltaV() - pim.correctedDeltaV(b)).norm(),
                              (re.deltaP() - pim.correctedDeltaP(b)).norm());
    Eigen::Vector3d uncorrected(so3Log(re.deltaR().transpose() * pim.deltaR()).norm(),
                                (re.deltaV() - pim.deltaV()).norm(), (re.deltaP() - pim.deltaP()).norm());
    return std::make_pair(corrected, uncorrected);
  };
  const auto [corr1, uncorr1] = errors(1.0);
  const auto [corr2, uncorr2] = errors(0.5);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(corr1[i], 0.02 * uncorr1[i]) << "component " << i;
    EXPECT_NEAR(corr2[i] / corr1[i], 0.25, 0.05) << "component " << i;
  }
}

TEST(ImuPreintegration, RejectsBadInput) {
  const AnalyticFlight f;
  auto imu = test::sampleImu(f, 200.0, 1.0);
  EXPECT_THROW(PreintegratedImu::integrate(imu, fromSeconds(0.5), fromSeconds(2.0), Vec6::Zero(),
                                           ImuNoiseParams()),
               InputError);
  imu[50].gyro.x() = std::nan("");
  EXPECT_THROW(PreintegratedImu::integrate(imu, fromSeconds(0.1), fromSeconds(0.9), Vec6::Zero(),
                                           ImuNoiseParams()),
               InputError);
}

}  // namespace
}  // namespace hdvio
