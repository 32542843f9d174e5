#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>

#include "deterministic_tcn.h"
#include "hdvio/core/error.h"
#include "hdvio/learned/residual_force_provider.h"
#include "hdvio/learned/tcn_weight_file.h"

namespace hdvio::learned {
namespace {

// 100 Hz inputs over 1 s with smooth thrust and gyro.
std::vector<DynamicsInput> flightInputs(double rate_hz = 100.0) {
  std::vector<DynamicsInput> s;
  for (int k = 0; k <= static_cast<int>(rate_hz); ++k) {
    const double t = k / rate_hz;
    s.push_back({fromSeconds(1.0 + t), Vec3(0.5 * std::sin(3 * t), 0.2, 9.8 + std::cos(2 * t)),
                 Vec3(0.3 * std::sin(5 * t), -0.2, 0.1 * t)});
  }
  return s;
}

std::shared_ptr<const ResidualForceModel> model(double sigma = 0.3) {
  return std::make_shared<const ResidualForceModel>(testing::deterministicTcn(), sigma);
}

TEST(ZeroProvider, ReturnsZeroForEverySampleInTheInterval) {
  ZeroResidualForceProvider zero;
  const auto s = flightInputs();
  const auto f = zero.residualForces(s, fromSeconds(1.2), fromSeconds(1.3), Vec3::Zero());
  ASSERT_EQ(f.size(), 11u);  // 1.20, 1.21, ..., 1.30
  EXPECT_EQ(f.front().t, fromSeconds(1.2));
  EXPECT_EQ(f.back().t, fromSeconds(1.3));
  for (const auto& r : f) {
    EXPECT_TRUE(r.force.isZero());
    EXPECT_TRUE(r.covariance.isZero());
  }
  EXPECT_THROW(zero.residualForces(s, fromSeconds(1.3), fromSeconds(1.2), Vec3::Zero()), std::invalid_argument);
}

// The diagnostic "perfect model": the true drag at every input sample, linear between the
// force samples (the external force is not part of it), held beyond their ends.
TEST(GroundTruthProvider, InterpolatesTheTrueDragAtEachSample) {
  std::vector<ForceSample> forces;
  for (int k = 0; k <= 20; ++k) {  // 20 Hz over 1 s, drag linear in time
    const double t = 0.05 * k;
    forces.push_back({fromSeconds(1.0 + t), Vec3(9.0, 9.0, 9.0), Vec3(-2.0 * t, 1.0 + t, 0.5)});
  }
  GroundTruthResidualForceProvider truth(forces);
  const auto s = flightInputs();
  const auto f = truth.residualForces(s, fromSeconds(1.2), fromSeconds(1.3), Vec3::Zero());
  ASSERT_EQ(f.size(), 11u);
  for (const auto& r : f) {
    const double t = toSeconds(r.t) - 1.0;
    EXPECT_LT((r.force - Vec3(-2.0 * t, 1.0 + t, 0.5)).norm(), 1e-12) << t;
  }
  std::vector<DynamicsInput> late = {{fromSeconds(3.0), Vec3::Zero(), Vec3::Zero()}};
  EXPECT_EQ(truth.residualForces(late, fromSeconds(3.0), fromSeconds(3.0), Vec3::Zero()).front().force,
            forces.back().drag);
  EXPECT_THROW(GroundTruthResidualForceProvider({}), std::invalid_argument);
  std::swap(forces[3], forces[4]);
  EXPECT_THROW(GroundTruthResidualForceProvider{forces}, std::invalid_argument);
}

TEST(TcnProvider, MatchesTheModelOnSampleAlignedWindows) {
  const auto m = model();
  TcnResidualForceProvider provider(m);
  EXPECT_NEAR(provider.historySeconds(), 0.09, 1e-12);
  const auto s = flightInputs();
  const Vec3 bias(0.01, -0.02, 0.005);
  const auto f = provider.residualForces(s, fromSeconds(1.5), fromSeconds(1.6), bias);
  ASSERT_EQ(f.size(), 11u);
  // On a 100 Hz grid the window is the 10 samples ending at t_k, gyro minus the bias.
  const std::size_t k = 55;  // t = 1.55
  ASSERT_EQ(f[5].t, s[k].t);
  std::vector<DynamicsInput> window(s.begin() + (k - 9), s.begin() + k + 1);
  for (auto& w : window) w.gyro -= bias;
  const ResidualForcePrediction expected = m->predict(window);
  EXPECT_LT((f[5].force - expected.force).norm(), 1e-6);
  EXPECT_GT(f[5].force.norm(), 1e-3);
  // Variance head: covariance = diag(exp(log-variance)), positive definite.
  EXPECT_GT(f[5].covariance.diagonal().minCoeff(), 0.0);
  EXPECT_TRUE(f[5].covariance.isDiagonal());
  // The bias matters.
  const auto f0 = provider.residualForces(s, fromSeconds(1.5), fromSeconds(1.6), Vec3::Zero());
  EXPECT_GT((f0[5].force - f[5].force).norm(), 1e-6);
}

TEST(TcnProvider, ResamplesHigherRateInputs) {
  const auto m = model();
  TcnResidualForceProvider provider(m);
  const auto s100 = flightInputs(100.0);
  const auto s400 = flightInputs(400.0);
  const auto a = provider.residualForces(s100, fromSeconds(1.5), fromSeconds(1.5), Vec3::Zero());
  const auto b = provider.residualForces(s400, fromSeconds(1.5), fromSeconds(1.5), Vec3::Zero());
  ASSERT_EQ(a.size(), 1u);
  ASSERT_EQ(b.size(), 1u);
  // Same underlying signal: the 400 Hz samples hit the same 10 ms grid exactly.
  EXPECT_LT((a[0].force - b[0].force).norm(), 1e-5);
}

TEST(TcnProvider, HoldsFirstSampleAtTheStartOfAFlight) {
  const auto m = model();
  const auto s = flightInputs();
  const auto w = m->windowEndingAt(s, s[3].t, Vec3::Zero());
  ASSERT_EQ(w.size(), 10u);
  for (int i = 0; i < 7; ++i) EXPECT_EQ(w[i].thrust, s[0].thrust);
  EXPECT_EQ(w[9].thrust, s[3].thrust);
  EXPECT_THROW(m->windowEndingAt(s, s.back().t + 1, Vec3::Zero()), std::invalid_argument);
}

TEST(ResidualForceModel, DefaultSigmaWithoutVarianceHead) {
  TcnWeights w = testing::deterministicTcn().weights();
  w.logvar_weight.resize(0, 0);
  w.logvar_bias.resize(0);
  const ResidualForceModel m(Tcn(TcnArchitecture::paper(false), w), 0.25);
  const auto s = flightInputs();
  const auto p = m.predict(m.windowEndingAt(s, s[50].t, Vec3::Zero()));
  EXPECT_TRUE(p.covariance.isApprox(0.0625 * Mat3::Identity()));
}

TEST(ProviderFactory, BuildsFromConfig) {
  const std::string dir = ::testing::TempDir();
  saveTcnWeights(testing::deterministicTcn(), dir + "/m.tcn");
  auto zero = makeResidualForceProvider(ConfigReader::fromString("type: zero\n"));
  EXPECT_EQ(zero->name(), "zero");
  auto tcn = makeResidualForceProvider(ConfigReader::fromString("type: tcn\nweights: m.tcn\ndefault_sigma: 0.5\n"), dir);
  EXPECT_EQ(tcn->name(), "tcn");
  EXPECT_THROW(makeResidualForceProvider(ConfigReader::fromString("type: tcn\nweigths: m.tcn\n")), InputError);
  EXPECT_THROW(makeResidualForceProvider(ConfigReader::fromString("type: magic\n")), InputError);
  EXPECT_THROW(makeResidualForceProvider(ConfigReader::fromString("type: tcn\nweights: missing.tcn\n"), dir), InputError);
  std::remove((dir + "/m.tcn").c_str());
}

}  // namespace
}  // namespace hdvio::learned

namespace hdvio::learned {
namespace {

TEST(ProviderGlue, PairsThrustWithInterpolatedGyroAndInterpolatesForces) {
  std::vector<ImuSample> imu;
  for (int k = 0; k <= 40; ++k) imu.push_back({fromSeconds(k / 400.0), Vec3(k, 2 * k, 0), Vec3::Zero()});
  std::vector<ThrustSample> thrust;
  for (int k = 0; k <= 10; ++k) thrust.push_back({fromSeconds(k / 100.0 + 0.00125), Vec3(0, 0, k)});
  const auto in = makeDynamicsInputs(imu, thrust, fromSeconds(0.02), fromSeconds(0.08));
  ASSERT_EQ(in.size(), 6u);  // 0.02125 ... 0.07125
  EXPECT_NEAR(in[0].gyro.x(), 8.5, 1e-9);  // halfway between IMU samples 8 and 9
  EXPECT_EQ(in[0].thrust.z(), 2.0);
  const std::vector<ResidualForce> f{{100, Vec3(1, 0, 0), Mat3::Zero()}, {200, Vec3(3, 0, 0), Mat3::Zero()}};
  EXPECT_NEAR(residualForceAt(f, 150).x(), 2.0, 1e-12);
  EXPECT_NEAR(residualForceAt(f, 50).x(), 1.0, 1e-12);
  EXPECT_NEAR(residualForceAt(f, 250).x(), 3.0, 1e-12);
  EXPECT_THROW(residualForceAt({}, 0), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio::learned
