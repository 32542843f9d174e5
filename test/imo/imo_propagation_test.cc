// The block-structured IMU propagation (imo_propagation.h) against the dense formulas
// A P A' + B Q B' and A Phi, over many random steps and over a long chained run.
#include <gtest/gtest.h>

#include <random>

#include "hdvio/backend/imo/imo_filter.h"
#include "hdvio/backend/imo/imo_propagation.h"

namespace hdvio::imo {
namespace {

struct RandomSource {
  std::mt19937 rng{11};
  std::normal_distribution<double> normal{0.0, 1.0};
  std::uniform_real_distribution<double> uniform{0.0, 1.0};
  Vec3 vec(double scale) { return scale * Vec3(normal(rng), normal(rng), normal(rng)); }
  Mat15 spd() {
    Mat15 L;
    for (int i = 0; i < 15; ++i)
      for (int j = 0; j < 15; ++j) L(i, j) = normal(rng);
    // Mixed scales as in the filter (rad^2, (m/s)^2, m^2, bias variances of 1e-8).
    const Eigen::Matrix<double, 15, 1> s =
        (Eigen::Matrix<double, 15, 1>() << Vec3::Constant(0.1), Vec3::Constant(1.0),
         Vec3::Constant(2.0), Vec3::Constant(1e-4), Vec3::Constant(1e-3))
            .finished();
    const Mat15 Ls = s.asDiagonal() * L;
    return Ls * Ls.transpose();
  }
  ImoNominalState state() {
    ImoNominalState x;
    x.R = so3Exp(vec(1.5));
    x.v = vec(5.0);
    x.p = vec(10.0);
    x.bg = vec(0.02);
    x.ba = vec(0.2);
    return x;
  }
};

double relativeError(const Mat15& a, const Mat15& b) { return (a - b).norm() / b.norm(); }

TEST(ImoPropagation, StructuredCovarianceEqualsDenseFormula) {
  RandomSource r;
  const Vec3 g(0.0, 0.0, -9.81);
  double worst_cov = 0.0, worst_phi = 0.0;
  for (int trial = 0; trial < 2000; ++trial) {
    const double dt = trial % 2 ? 0.0025 : 0.001 + 0.02 * r.uniform(r.rng);
    const NominalStep s = propagateStep(r.state(), r.vec(3.0), r.vec(10.0) + Vec3(0, 0, 9.81), dt, g);
    const Mat15 A = s.transition.dense();
    const Eigen::Matrix<double, 15, 6> B = s.transition.noiseInput();
    const double qg = 1e-8 / dt, qa = 1e-4 / dt;
    Eigen::Matrix<double, 6, 1> q;
    q << Vec3::Constant(qg), Vec3::Constant(qa);

    const Mat15 P0 = r.spd();
    const Mat15 dense = A * P0 * A.transpose() + B * q.asDiagonal() * B.transpose();
    Mat15 structured = P0;
    propagateCovariance(s.transition, qg, qa, &structured);
    worst_cov = std::max(worst_cov, relativeError(structured, dense));

    Mat15 phi = r.spd();  // any 15 x 15 block
    const Mat15 phi_dense = A * phi;
    applyTransition(s.transition, &phi);
    worst_phi = std::max(worst_phi, relativeError(phi, phi_dense));
  }
  std::printf("structured vs dense, 2000 random steps: covariance %.1e, transition %.1e (relative)\n",
              worst_cov, worst_phi);
  EXPECT_LT(worst_cov, 1e-12);
  EXPECT_LT(worst_phi, 1e-12);
}

TEST(ImoPropagation, FilterCovarianceEqualsDenseRecursionOverManySteps) {
  // 4000 steps at 400 Hz with two clones: the filter's covariance (structured, lazy cross
  // block) against the dense recursion on the full matrix.
  RandomSource r;
  ImoFilterOptions o;
  ImoFilter filter(o);
  ImoNominalState x0 = r.state();
  filter.initialize(x0);
  filter.addClone();
  const double dt = 0.0025;
  Eigen::MatrixXd P = filter.covariance();
  for (int k = 0; k < 4000; ++k) {
    if (k == 2000) {
      filter.addClone();
      P = filter.covariance();
    }
    const Vec3 gyro = Vec3(0.5 * std::sin(0.01 * k), 0.3, -0.2) + r.vec(0.01);
    const Vec3 accel = Vec3(1.0, -0.5 * std::cos(0.005 * k), 9.81) + r.vec(0.1);
    const PropagationStep s = propagateNominal(filter.state(), gyro, accel, dt, o.gravity);
    const int n = static_cast<int>(P.rows());
    Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n, n);
    A.topLeftCorner<15, 15>() = s.A;
    Eigen::Matrix<double, 6, 1> q;
    q << Vec3::Constant(o.gyro_noise_density * o.gyro_noise_density / dt),
        Vec3::Constant(o.accel_noise_density * o.accel_noise_density / dt);
    P = A * P * A.transpose();
    P.topLeftCorner<15, 15>() += s.B * q.asDiagonal() * s.B.transpose();
    P.diagonal().segment<3>(9).array() += o.gyro_random_walk * o.gyro_random_walk * dt;
    P.diagonal().segment<3>(12).array() += o.accel_random_walk * o.accel_random_walk * dt;
    P = (0.5 * (P + P.transpose())).eval();
    filter.propagate(gyro, accel, filter.state().t + fromSeconds(dt));
  }
  const double err = (filter.covariance() - P).norm() / P.norm();
  std::printf("filter vs dense recursion after 4000 steps: %.1e relative\n", err);
  EXPECT_LT(err, 1e-12);
}

}  // namespace
}  // namespace hdvio::imo
