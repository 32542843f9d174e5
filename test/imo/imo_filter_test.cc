// The IMO filter's algebra: propagation against a noise-free analytic flight, propagation and
// update Jacobians against finite differences, the lazy cross-covariance, Joseph-form
// covariance staying symmetric positive definite, and the chi-square gate.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cstdio>
#include <random>

#include "analytic_trajectory.h"
#include "hdvio/backend/imo/imo_filter.h"

namespace hdvio::imo {
namespace {

using testing::imuAt;
using testing::simulateImu;
using testing::trajectoryAt;

ImoNominalState exactState(double t) {
  const auto s = trajectoryAt(t);
  ImoNominalState x;
  x.t = fromSeconds(t);
  x.R = s.R;
  x.v = s.v;
  x.p = s.p;
  return x;
}

// Error of b relative to a in the filter's error-state convention (right: b.R = a.R Exp(d),
// left: b.R = Exp(d) a.R).
Eigen::Matrix<double, 15, 1> stateError(const ImoNominalState& a, const ImoNominalState& b,
                                        RotationError e = RotationError::kRight) {
  Eigen::Matrix<double, 15, 1> d;
  d << so3Log(e == RotationError::kLeft ? Mat3(b.R * a.R.transpose()) : Mat3(a.R.transpose() * b.R)),
      b.v - a.v, b.p - a.p, b.bg - a.bg, b.ba - a.ba;
  return d;
}

ImoNominalState perturbed(const ImoNominalState& x, const Eigen::Matrix<double, 15, 1>& d,
                          RotationError e = RotationError::kRight) {
  ImoNominalState y = x;
  y.R = e == RotationError::kLeft ? Mat3(so3Exp(d.segment<3>(0)) * x.R) : Mat3(x.R * so3Exp(d.segment<3>(0)));
  y.v += d.segment<3>(3);
  y.p += d.segment<3>(6);
  y.bg += d.segment<3>(9);
  y.ba += d.segment<3>(12);
  return y;
}

TEST(ImoPropagation, FollowsNoiseFreeAnalyticFlight) {
  for (const double rate : {100.0, 400.0}) {
    const auto imu = simulateImu(rate, 6.0);
    ImoFilter filter(ImoFilterOptions{});
    filter.initialize(exactState(0.0));
    for (std::size_t k = 0; k + 1 < imu.size(); ++k)
      filter.propagate(0.5 * (imu[k].gyro + imu[k + 1].gyro),
                       0.5 * (imu[k].accel + imu[k + 1].accel), imu[k + 1].t);
    const auto truth = exactState(6.0);
    const auto err = stateError(truth, filter.state());
    SCOPED_TRACE(rate);
    // Trapezoidal inputs, mid-step attitude: second order (errors / 16 from 100 to 400 Hz).
    const double scale = rate < 200 ? 16.0 : 1.0;
    EXPECT_LT(err.segment<3>(0).norm(), scale * 2e-5);  // rad
    EXPECT_LT(err.segment<3>(3).norm(), scale * 2e-4);  // m/s
    EXPECT_LT(err.segment<3>(6).norm(), scale * 5e-4);  // m
    std::printf("noise-free propagation, %.0f Hz, 6 s: |dtheta| %.2e rad |dv| %.2e m/s |dp| %.2e m\n",
                rate, err.segment<3>(0).norm(), err.segment<3>(3).norm(), err.segment<3>(6).norm());
  }
}

// Both attitude error conventions (rotation_error), both propagation steps.
TEST(ImoPropagation, JacobiansMatchFiniteDifferences) {
  for (const RotationError e : {RotationError::kRight, RotationError::kLeft})
  for (bool start : {false, true}) {  // mid-step attitude, release (start-attitude) step
    SCOPED_TRACE(start ? "start attitude" : "mid-step attitude");
    SCOPED_TRACE(e == RotationError::kLeft ? "left error" : "right error");
    ImoNominalState x = exactState(1.3);
    x.bg = Vec3(0.01, -0.02, 0.015);
    x.ba = Vec3(0.1, 0.05, -0.2);
    const ImuSample m = imuAt(1.3, 0);
    const double dt = 0.01;
    const Vec3 g = gravityWorld();
    const PropagationStep ref = propagateNominal(x, m.gyro, m.accel, dt, g, start, e);
    const double eps = 1e-6;
    for (int i = 0; i < 15; ++i) {
      Eigen::Matrix<double, 15, 1> d = Eigen::Matrix<double, 15, 1>::Zero();
      d(i) = eps;
      const auto plus = propagateNominal(perturbed(x, d, e), m.gyro, m.accel, dt, g, start, e);
      const auto minus = propagateNominal(perturbed(x, -d, e), m.gyro, m.accel, dt, g, start, e);
      const Eigen::Matrix<double, 15, 1> col =
          (stateError(ref.state, plus.state, e) - stateError(ref.state, minus.state, e)) / (2 * eps);
      EXPECT_LT((col - ref.A.col(i)).norm(), 1e-7) << "column " << i << "\n" << col.transpose()
                                                    << "\n" << ref.A.col(i).transpose();
    }
    // Noise inputs: gyro noise n_g enters as gyro + n_g, accel noise as accel + n_a.
    for (int i = 0; i < 6; ++i) {
      Vec3 dg = Vec3::Zero(), da = Vec3::Zero();
      (i < 3 ? dg : da)(i % 3) = eps;
      const auto plus = propagateNominal(x, m.gyro + dg, m.accel + da, dt, g, start, e);
      const auto minus = propagateNominal(x, m.gyro - dg, m.accel - da, dt, g, start, e);
      const Eigen::Matrix<double, 15, 1> col =
          (stateError(ref.state, plus.state, e) - stateError(ref.state, minus.state, e)) / (2 * eps);
      // B is d(error)/d(noise) with error = truth (-) estimate and measurement = truth + noise,
      // so perturbing the measurement moves the estimate by -B.
      EXPECT_LT((col + ref.B.col(i)).norm(), 1e-7) << "noise column " << i;
    }
  }
}

// A filter with a few clones and some history, shared by the update tests.
ImoFilter filterWithClones(int clones, ImoFilterOptions options = {}) {
  const auto imu = simulateImu(100.0, 0.05 * clones + 0.2);
  ImoFilter filter(options);
  filter.initialize(exactState(0.0));
  filter.addClone();
  for (std::size_t k = 0; k + 1 < imu.size(); ++k) {
    filter.propagate(imu[k].gyro, imu[k].accel, imu[k + 1].t);
    if ((k + 1) % 5 == 0 && static_cast<int>(filter.clones().size()) < clones) filter.addClone();
  }
  return filter;
}

// Central differences of h(filter) through inject (3 x (15 + 9 N)): the Jacobian in the
// filter's own error-state convention.
template <class F>
Eigen::MatrixXd injectedJacobian(const ImoFilter& filter, F h) {
  const int n = static_cast<int>(filter.covariance().rows());
  const double eps = 1e-6;
  Eigen::MatrixXd J(3, n);
  for (int i = 0; i < n; ++i) {
    ImoFilter plus = filter, minus = filter;
    Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
    d(i) = eps;
    plus.inject(d);
    minus.inject(-d);
    J.col(i) = (h(plus) - h(minus)) / (2 * eps);
  }
  return J;
}

TEST(ImoUpdate, MeasurementJacobianMatchesFiniteDifferences) {
  ImoFilter filter = filterWithClones(6);
  ASSERT_EQ(filter.clones().size(), 6u);
  const int n = static_cast<int>(filter.covariance().rows());
  Mat3 full;  // a drag model's velocity coefficient is a full matrix
  full << 0.48, 0.01, -0.02, 0.015, 0.47, 0.005, -0.01, 0.02, 0.49;
  for (const Mat3& c : {Mat3::Zero().eval(), (0.5 * Mat3::Identity()).eval(), full}) {
    RelativePositionMeasurement m;
    m.clone_i = 1;
    m.clone_j = 5;
    m.velocity_matrix = c;
    const Eigen::MatrixXd H = filter.measurementJacobian(m);
    const Eigen::MatrixXd fd = injectedJacobian(filter, [&](const ImoFilter& f) { return f.predictMeasurement(m); });
    for (int i = 0; i < n; ++i)
      EXPECT_LT((fd.col(i) - H.col(i)).norm(), 1e-7) << "c " << c(0, 0) << " column " << i;
  }
}

// An attitude-dependent prediction g(R_i) = R_i c (right Jacobian -R_i [c]x, what a model
// source hands over as attitude_jacobian): the filter's H, in either convention, against
// finite differences of p_j - p_i - g(R_i) through inject (which perturbs in that convention).
TEST(ImoUpdate, AttitudeJacobianIsConvertedToTheFiltersConvention) {
  const Vec3 c(0.3, -0.2, 0.1);
  for (const RotationError e : {RotationError::kRight, RotationError::kLeft}) {
    SCOPED_TRACE(e == RotationError::kLeft ? "left error" : "right error");
    ImoFilterOptions o;
    o.rotation_error = e;
    ImoFilter filter = filterWithClones(4, o);
    RelativePositionMeasurement m;
    m.clone_i = 1;
    m.clone_j = 3;
    m.attitude_jacobian = -filter.clones()[1].R * hat(c);
    const Eigen::MatrixXd H = filter.measurementJacobian(m);
    auto h = [&](const ImoFilter& f) { return Vec3(f.predictMeasurement(m) - f.clones()[1].R * c); };
    const int n = static_cast<int>(H.cols());
    const Eigen::MatrixXd fd = injectedJacobian(filter, h);
    for (int i = 0; i < n; ++i) EXPECT_LT((fd.col(i) - H.col(i)).norm(), 1e-7) << "column " << i;
    // The same for a generic Jacobian (gate corners): jacobianInFilterConvention.
    Eigen::MatrixXd H_right = Eigen::MatrixXd::Zero(3, n);
    H_right.middleCols<3>(15 + 9 * 1) = -filter.clones()[1].R * hat(c);
    H_right.middleCols<3>(0) = filter.state().R * hat(c);  // of +R c for the evolving state
    const Eigen::MatrixXd Hf = filter.jacobianInFilterConvention(H_right);
    auto g = [&](const ImoFilter& f) { return Vec3(f.state().R * c - f.clones()[1].R * c); };
    const Eigen::MatrixXd fd_g = injectedJacobian(filter, g);
    for (int i = 0; i < n; ++i) EXPECT_LT((fd_g.col(i) + Hf.col(i)).norm(), 1e-7) << "generic column " << i;
  }
}

TEST(ImoCovariance, LazyCrossCovarianceEqualsFullPropagation) {
  ImoFilter filter = filterWithClones(4);
  const Eigen::MatrixXd P0 = filter.covariance();
  const int n = static_cast<int>(P0.rows());
  ImoFilterOptions o;
  Eigen::MatrixXd P = P0;
  for (int k = 0; k < 7; ++k) {
    const ImuSample m = imuAt(0.5 + 0.01 * k, 0);
    const Timestamp t_next = filter.state().t + fromSeconds(0.01);
    const PropagationStep s = propagateNominal(filter.state(), m.gyro, m.accel, 0.01, o.gravity);
    Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n);
    A.topLeftCorner(15, 15) = s.A;
    Eigen::MatrixXd Qd = Eigen::MatrixXd::Zero(n, n);
    Eigen::Matrix<double, 6, 1> w;
    w << Vec3::Constant(o.gyro_noise_density * o.gyro_noise_density / 0.01),
        Vec3::Constant(o.accel_noise_density * o.accel_noise_density / 0.01);
    Qd.topLeftCorner(15, 15) = s.B * w.asDiagonal() * s.B.transpose();
    Qd.diagonal().segment<3>(9).array() += o.gyro_random_walk * o.gyro_random_walk * 0.01;
    Qd.diagonal().segment<3>(12).array() += o.accel_random_walk * o.accel_random_walk * 0.01;
    P = A * P * A.transpose() + Qd;
    filter.propagate(m.gyro, m.accel, t_next);
  }
  EXPECT_LT((filter.covariance() - P).norm(), 1e-12 * (1.0 + P.norm()));
}

TEST(ImoCovariance, JosephUpdatesKeepCovarianceSymmetricPositiveDefinite) {
  ImoFilter filter = filterWithClones(11);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  const auto imu = simulateImu(100.0, 6.0);
  std::size_t k = 0;
  for (int round = 0; round < 40; ++round) {
    const int nc = static_cast<int>(filter.clones().size());
    RelativePositionMeasurement m;
    m.clone_i = 0;
    m.clone_j = nc - 1;
    m.z = filter.predictMeasurement(m) + 0.01 * Vec3(noise(rng), noise(rng), noise(rng));
    m.covariance = Mat3::Identity() * (round % 2 ? 1e-4 : 1e-8);  // also very confident ones
    m.velocity_coefficient = round % 3 == 0 ? 0.5 : 0.0;
    const double trace_before = filter.covariance().trace();
    ASSERT_EQ(filter.update(m), UpdateOutcome::kApplied);
    const Eigen::MatrixXd P = filter.covariance();
    EXPECT_LT((P - P.transpose()).norm(), 1e-12 * P.norm());
    // A fresh clone equals the evolving state, so P is singular up to round-off.
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(P).eigenvalues().minCoeff(),
              -1e-12 * P.norm())
        << "round " << round;
    EXPECT_GT(P.diagonal().minCoeff(), 0.0);
    EXPECT_LE(P.trace(), trace_before);
    filter.marginalizeClone(0);
    for (int s = 0; s < 5; ++s, ++k)
      filter.propagate(imu[k % imu.size()].gyro, imu[k % imu.size()].accel,
                       filter.state().t + fromSeconds(0.01));
    filter.addClone();
  }
}

// The O(n^2) update against the Joseph form written out densely with H and K, for
// measurements with and without the velocity and attitude terms.
TEST(ImoUpdate, ExpandedUpdateEqualsDenseJosephForm) {
  Mat3 attitude;
  attitude << 0.0, -0.02, 0.01, 0.02, 0.0, -0.03, -0.01, 0.03, 0.0;
  for (int variant = 0; variant < 3; ++variant) {
    ImoFilter filter = filterWithClones(11);
    RelativePositionMeasurement m;
    m.clone_i = 2;
    m.clone_j = 10;
    m.z = filter.predictMeasurement(m) + Vec3(0.03, -0.02, 0.01);
    m.covariance = Vec3(1e-4, 2e-4, 3e-4).asDiagonal();
    if (variant >= 1) m.velocity_coefficient = 0.5;
    if (variant == 2) m.attitude_jacobian = attitude;
    const Eigen::MatrixXd P = filter.covariance();
    const Eigen::MatrixXd H = filter.measurementJacobian(m);
    const Eigen::MatrixXd K = P * H.transpose() * (H * P * H.transpose() + m.covariance).inverse();
    const Eigen::MatrixXd IKH = Eigen::MatrixXd::Identity(P.rows(), P.cols()) - K * H;
    const Eigen::MatrixXd expected = IKH * P * IKH.transpose() + K * m.covariance * K.transpose();
    ASSERT_EQ(filter.update(m), UpdateOutcome::kApplied);
    EXPECT_LT((filter.covariance() - expected).norm(), 1e-12 * expected.norm()) << "variant " << variant;
    EXPECT_EQ(filter.covariance(), filter.covariance().transpose());  // symmetric exactly
  }
}

// Cloning and marginalization work in place in a storage that grows: their covariance must be
// the bordered / reduced matrix, also past the initial capacity and for a middle clone.
TEST(ImoCovariance, InPlaceCloningAndMarginalizationMatchTheirDefinitions) {
  ImoFilter filter = filterWithClones(12);
  const auto imu = simulateImu(100.0, 2.0);
  for (int round = 0; round < 12; ++round) {  // 24 clones: beyond the initial storage
    for (int s = 0; s < 5; ++s)
      filter.propagate(imu[5 * round + s].gyro, imu[5 * round + s].accel, filter.state().t + fromSeconds(0.01));
    const Eigen::MatrixXd P = filter.covariance();
    const int n = static_cast<int>(P.rows());
    filter.addClone();
    Eigen::MatrixXd bordered(n + 9, n + 9);
    bordered << P, P.leftCols(9), P.topRows(9), P.topLeftCorner(9, 9);
    ASSERT_EQ(filter.covariance(), bordered) << "round " << round;
  }
  for (const int k : {0, 7, 21}) {  // first, middle, last (24, 23, 22 clones)
    const Eigen::MatrixXd P = filter.covariance();
    const int n = static_cast<int>(P.rows()), o = 15 + 9 * k;
    std::vector<int> keep;
    for (int i = 0; i < n; ++i)
      if (i < o || i >= o + 9) keep.push_back(i);
    filter.marginalizeClone(k);
    EXPECT_EQ(filter.covariance(), P(keep, keep)) << "clone " << k;
  }
}

TEST(ImoUpdate, GateRejectsOutliersOnlyWhenEnabled) {
  for (const double factor : {-1.0, 1.0}) {
    ImoFilterOptions o;
    o.mahalanobis_factor = factor;
    ImoFilter filter = filterWithClones(11, o);
    RelativePositionMeasurement m;
    m.clone_i = 0;
    m.clone_j = 10;
    m.covariance = Mat3::Identity() * 1e-4;
    m.z = filter.predictMeasurement(m) + Vec3(0.0, 0.0, 0.01);
    EXPECT_EQ(filter.update(m), UpdateOutcome::kApplied);  // 1 sigma: always fine
    m.z = filter.predictMeasurement(m) + Vec3(5.0, 0.0, 0.0);
    EXPECT_EQ(filter.update(m),
              factor > 0 ? UpdateOutcome::kRejectedByGate : UpdateOutcome::kApplied);
    EXPECT_GT(filter.lastMahalanobis(), 11.345);
  }
}

}  // namespace
}  // namespace hdvio::imo
