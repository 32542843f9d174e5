// The preintegration factors' noiseModel() is their real covariance: what anything
// reading the model sees (marginalization, diagnostics, covariance recovery) is the
// preintegrated covariance, and it is the model that whitens what Ceres sees.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <type_traits>
#include <vector>

#include "hdvio/factors/dynamics_factors.h"
#include "hdvio/factors/imu_factor.h"
#include "test_support.h"

namespace hdvio {
namespace {
using namespace symbols;
using test::makeDynamics;
using test::randomStates;
using test::randomSteps;

// The whitened residual Ceres sees is S r with S from noiseModel(), r the factor's own
// (unwhitened) residual, and S Sigma S^T = I for the covariance the model reports.
template <class Factor>
void expectModelWhitens(const Factor& f, const Values& values) {
  const NoiseModel& noise = f.noiseModel();
  const Eigen::MatrixXd S = noise.sqrtInformationMatrix();
  const Eigen::MatrixXd C = noise.covarianceMatrix();
  EXPECT_LT((S * C * S.transpose() - Eigen::MatrixXd::Identity(f.dim(), f.dim())).cwiseAbs().maxCoeff(), 1e-9);
  std::vector<const double*> x;
  for (Key k : f.keys()) x.push_back(values.data(k));
  Eigen::VectorXd raw(f.dim());
  ASSERT_TRUE(f.evaluateError(x.data(), raw.data(), nullptr));
  Eigen::VectorXd whitened;
  ASSERT_TRUE(f.whitenedError(values, &whitened));
  const Eigen::VectorXd expected = S * raw;
  EXPECT_LT((whitened - expected).cwiseAbs().maxCoeff(), 1e-9 * (1.0 + expected.cwiseAbs().maxCoeff()))
      << "whitened " << whitened.transpose() << "\nS r     " << expected.transpose();
}

TEST(NoiseTruth, ImuFactorNoiseModelIsThePreintegratedCovariance) {
  std::mt19937 rng(21);
  std::vector<ImuStep> steps;
  for (const auto& s : randomSteps(rng, 60)) steps.push_back({s.dt, s.gyro, s.accel});
  ImuNoiseParams params;
  params.gyro_random_walk = 3e-4;
  params.accel_random_walk = 5e-3;
  auto pim = std::make_shared<PreintegratedImu>(PreintegratedImu::integrate(steps, Vec6::Zero(), params));
  const ImuFactor f(X(0), V(0), B(0), X(1), V(1), B(1), pim);
  const Eigen::MatrixXd C = f.noiseModel().covarianceMatrix();
  ASSERT_EQ(C.rows(), 15);
  const double scale = pim->covariance().cwiseAbs().maxCoeff();
  EXPECT_LT((C.topLeftCorner(9, 9) - pim->covariance()).cwiseAbs().maxCoeff(), 1e-14 * scale);
  EXPECT_EQ(C.topRightCorner(9, 6).cwiseAbs().maxCoeff(), 0.0);
  Eigen::VectorXd walk(6);
  walk << Vec3::Constant(3e-4 * 3e-4 * pim->dt()), Vec3::Constant(5e-3 * 5e-3 * pim->dt());
  const Eigen::MatrixXd expected_walk = walk.asDiagonal();
  EXPECT_LT((C.bottomRightCorner(6, 6) - expected_walk).cwiseAbs().maxCoeff(), 1e-15);
  expectModelWhitens(f, randomStates(rng, Mat3::Identity()));
}

template <class Factor>
class DynamicsNoiseTruth : public ::testing::Test {};
using DynamicsFactorTypes = ::testing::Types<HdvioDynamicsFactor, VimoDynamicsFactor, VidDynamicsFactor>;
TYPED_TEST_SUITE(DynamicsNoiseTruth, DynamicsFactorTypes);

TYPED_TEST(DynamicsNoiseTruth, NoiseModelIsThePreintegratedCovariance) {
  std::mt19937 rng(22);
  auto pit = std::make_shared<PreintegratedThrust>(
      PreintegratedThrust::integrate(randomSteps(rng, 60), Vec6::Zero(), ThrustNoiseParams()));
  DynamicsFactorParams params;
  params.force_random_walk = 0.7;
  params.force_prior_sigma = 2.5;
  const auto f = makeDynamics<TypeParam>(pit, params);
  const Eigen::MatrixXd C = f->noiseModel().covarianceMatrix();
  ASSERT_EQ(C.rows(), 9);
  Eigen::Matrix<double, 6, 6> ab = pit->alphaBetaCovariance();
  if (std::is_same_v<TypeParam, HdvioDynamicsFactor>) {
    // plus the walk's bridge between the interpolated end points (checked by Monte Carlo below)
    const double q = 0.7 * 0.7, T = pit->dt();
    ab.topLeftCorner<3, 3>().diagonal().array() += q * std::pow(T, 5) / 45.0;
    ab.topRightCorner<3, 3>().diagonal().array() += q * std::pow(T, 4) / 24.0;
    ab.bottomLeftCorner<3, 3>().diagonal().array() += q * std::pow(T, 4) / 24.0;
    ab.bottomRightCorner<3, 3>().diagonal().array() += q * std::pow(T, 3) / 12.0;
  }
  EXPECT_LT((C.topLeftCorner(6, 6) - ab).cwiseAbs().maxCoeff(), 1e-14 * ab.cwiseAbs().maxCoeff());
  EXPECT_EQ(C.topRightCorner(6, 3).cwiseAbs().maxCoeff(), 0.0);
  const double sigma_f = std::is_same_v<TypeParam, HdvioDynamicsFactor> ? 0.7 * std::sqrt(pit->dt()) : 2.5;
  const Eigen::MatrixXd expected_force = Mat3::Identity() * (sigma_f * sigma_f);
  EXPECT_LT((C.bottomRightCorner(3, 3) - expected_force).cwiseAbs().maxCoeff(), 1e-12);
  expectModelWhitens(*f, randomStates(rng, Mat3::Identity()));
}

// hdvio's force is a random walk that the factor interpolates linearly between f_i and f_j:
// with exact thrust and states, the alpha / beta residuals are the walk's deviation from that
// line integrated, and their spread is the bridge part of the noise model. Monte Carlo over
// walks of density q on a 50-ms interval (the image rate), one axis.
TEST(DynamicsNoiseTruth, HdvioWalkBridgeCovarianceMatchesMonteCarlo) {
  std::mt19937 rng(24);
  std::normal_distribution<double> normal;
  const double rw = 2.0, q = rw * rw, T = 0.05;
  const int steps = 200, trials = 20000;
  const double h = T / steps;
  double saa = 0.0, sab = 0.0, sbb = 0.0, sbf = 0.0;
  for (int n = 0; n < trials; ++n) {
    double w = 0.0, alpha = 0.0, beta = 0.0;  // walk from f_i = 0; residual integrals
    std::vector<double> path(steps + 1, 0.0);
    for (int k = 1; k <= steps; ++k) path[k] = path[k - 1] + std::sqrt(q * h) * normal(rng);
    w = path[steps];
    for (int k = 0; k < steps; ++k) {  // midpoint rule for the force minus its interpolation
      const double t = (k + 0.5) * h;
      const double dev = 0.5 * (path[k] + path[k + 1]) - w * t / T;
      beta += dev * h;
      alpha += dev * (T - t) * h;
    }
    saa += alpha * alpha;
    sab += alpha * beta;
    sbb += beta * beta;
    sbf += beta * w;
  }
  DynamicsFactorParams params;
  params.force_random_walk = rw;
  std::vector<DynamicsStep> exact(10, DynamicsStep{T / 10, Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  ThrustNoiseParams tiny;
  tiny.thrust_noise_density = Vec3::Constant(1e-12);
  tiny.thrust_direction_noise_density = 1e-12;
  tiny.gyro_noise_density = 1e-12;
  tiny.gyro_random_walk = 1e-12;
  auto pit = std::make_shared<PreintegratedThrust>(PreintegratedThrust::integrate(exact, Vec6::Zero(), tiny));
  const Eigen::MatrixXd C = HdvioDynamicsFactor::noiseFor(*pit, params)->covarianceMatrix();
  EXPECT_NEAR(saa / trials, C(0, 0), 0.05 * C(0, 0));
  EXPECT_NEAR(sab / trials, C(0, 3), 0.05 * C(0, 3));
  EXPECT_NEAR(sbb / trials, C(3, 3), 0.05 * C(3, 3));
  // The bridge is independent of the end-point increment: no cross term with r_f.
  EXPECT_LT(std::abs(sbf / trials), 0.05 * std::sqrt(C(3, 3) * C(6, 6)));
  EXPECT_EQ(C(3, 6), 0.0);
}

// Each factor declares only keys its residual depends on: no all-zero Jacobian block.
TYPED_TEST(DynamicsNoiseTruth, EveryDeclaredKeyHasANonzeroJacobian) {
  std::mt19937 rng(23);
  auto pit = std::make_shared<PreintegratedThrust>(
      PreintegratedThrust::integrate(randomSteps(rng, 60), Vec6::Zero(), ThrustNoiseParams()));
  const auto f = makeDynamics<TypeParam>(pit, DynamicsFactorParams());
  Linearization lin;
  ASSERT_TRUE(f->linearize(randomStates(rng, Mat3::Identity()), &lin));
  for (std::size_t i = 0; i < lin.jacobians.size(); ++i)
    EXPECT_GT(lin.jacobians[i].cwiseAbs().maxCoeff(), 1e-6) << "key " << i;
}

}  // namespace
}  // namespace hdvio
