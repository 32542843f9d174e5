// The preintegration factors' noiseModel() is their real covariance (issue 18): what anything
// reading the model sees (marginalization, diagnostics, covariance recovery) is the
// preintegrated covariance, and it is the model that whitens what Ceres sees.
#include <gtest/gtest.h>

#include <random>

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
  const Eigen::Matrix<double, 6, 6> ab = pit->alphaBetaCovariance();
  EXPECT_LT((C.topLeftCorner(6, 6) - ab).cwiseAbs().maxCoeff(), 1e-14 * ab.cwiseAbs().maxCoeff());
  EXPECT_EQ(C.topRightCorner(6, 3).cwiseAbs().maxCoeff(), 0.0);
  const double sigma_f = std::is_same_v<TypeParam, HdvioDynamicsFactor> ? 0.7 * std::sqrt(pit->dt()) : 2.5;
  const Eigen::MatrixXd expected_force = Mat3::Identity() * (sigma_f * sigma_f);
  EXPECT_LT((C.bottomRightCorner(3, 3) - expected_force).cwiseAbs().maxCoeff(), 1e-12);
  expectModelWhitens(*f, randomStates(rng, Mat3::Identity()));
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
