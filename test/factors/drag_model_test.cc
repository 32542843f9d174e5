// Drag at the state's velocity (drag_model.h): integrated over a keyframe interval of the
// analytic flight it must reproduce the flight, which the preintegrated thrust alone does not.
#include <gtest/gtest.h>

#include <cstdio>

#include "hdvio/factors/drag_model.h"
#include "hdvio/factors/thrust_preintegration.h"
#include "test_support.h"

namespace hdvio {
namespace {
using test::AnalyticFlight;

DragLaw vehicleDrag() {
  DragLaw d;
  d.linear = Vec3(0.3, 0.25, 0.05);
  d.rotor = Vec3(0.2, 0.15, 0.07);
  d.quadratic = Vec3(0.02, 0.03, 0.01);
  d.lift = 0.016;
  return d;
}

// alpha / beta errors of (thrust preintegration + drag integral) against the flight over
// [t_i, t_i + 0.05 s], with thrust chosen so that thrust + drag(R^T v) explains the flight.
Eigen::Vector2d errorsOverInterval(double t_i, const DragLaw& model_in_factor) {
  const AnalyticFlight f;
  const DragLaw truth = vehicleDrag();
  const double t_j = t_i + 0.05;
  const auto imu = test::sampleImu(f, 1000.0, t_j + 0.1);
  std::vector<ThrustSample> thrust;
  for (const ImuSample& s : imu) {
    const double t = toSeconds(s.t);
    const Vec3 u = f.R(t).transpose() * f.v(t);
    // The law's rotor term depends on the thrust it corrects: a few fixed-point steps.
    Vec3 T = f.specificForce(t);
    for (int it = 0; it < 20; ++it) T = f.specificForce(t) - truth.force(u, T.norm());
    thrust.push_back({s.t, T});
  }
  const auto pit = PreintegratedThrust::integrate(imu, thrust, fromSeconds(t_i), fromSeconds(t_j),
                                                  Vec6::Zero(), ThrustNoiseParams());
  const Mat3 RiT = f.R(t_i).transpose();
  const double dt = t_j - t_i;
  const Vec3 g = gravityWorld();
  const Vec3 beta = RiT * (f.v(t_j) - f.v(t_i) - g * dt);
  const Vec3 alpha = RiT * (f.p(t_j) - f.p(t_i) - f.v(t_i) * dt - 0.5 * g * dt * dt);
  const DragIntegral drag = integrateDrag(pit, model_in_factor, RiT * f.v(t_i), RiT * f.v(t_j));
  return Eigen::Vector2d((pit.alpha() + drag.alpha - alpha).norm(),
                         (pit.beta() + drag.beta - beta).norm());
}

TEST(DragLaw, IntegratedAtTheStateVelocityReproducesTheFlight) {
  for (double t_i : {0.2, 0.9, 1.7}) {
    const Eigen::Vector2d with = errorsOverInterval(t_i, vehicleDrag());
    const Eigen::Vector2d without = errorsOverInterval(t_i, DragLaw());
    std::printf("t_i %.1f: alpha / beta error with drag %.2g / %.2g, without %.2g / %.2g\n", t_i,
                with[0], with[1], without[0], without[1]);
    EXPECT_LT(with[0], 2e-6);  // m
    EXPECT_LT(with[1], 5e-5);  // m/s
    EXPECT_GT(without[1], 100.0 * with[1]);
  }
}

TEST(DragLaw, JacobianMatchesNumerical) {
  const DragLaw d = vehicleDrag();
  for (double thrust : {0.0, 9.81, 35.0})
    for (const Vec3& u : {Vec3(3.0, -2.0, 1.0), Vec3(0.1, 0.0, -0.2), Vec3(-8.0, 5.0, 0.5)}) {
      Mat3 numerical;
      for (int k = 0; k < 3; ++k) {
        const Vec3 h = 1e-6 * Vec3::Unit(k);
        numerical.col(k) = (d.force(u + h, thrust) - d.force(u - h, thrust)) / 2e-6;
      }
      EXPECT_LT((numerical - d.jacobian(u, thrust)).cwiseAbs().maxCoeff(), 1e-8) << thrust;
    }
  EXPECT_TRUE(d.force(Vec3::Zero(), 9.81).isZero(0.0));
  EXPECT_FALSE(DragLaw().enabled());
  DragLaw lift_only;
  lift_only.lift = 0.01;
  EXPECT_TRUE(lift_only.enabled());
}

// The rotor term grows with the rotor-speed sum, sqrt(thrust / hover thrust): at four times
// the hover thrust it is twice the hover value; the lift term pushes along +z with the
// horizontal speed squared.
TEST(DragLaw, RotorTermScalesWithSqrtThrustAndLiftWithHorizontalSpeed) {
  DragLaw d;
  d.rotor = Vec3(0.2, 0.1, 0.05);
  const Vec3 u(2.0, -1.0, 0.5);
  const Vec3 hover = d.force(u, DragLaw::kHoverThrust);
  EXPECT_LT((hover + d.rotor.cwiseProduct(u)).norm(), 1e-12);
  EXPECT_LT((d.force(u, 4.0 * DragLaw::kHoverThrust) - 2.0 * hover).norm(), 1e-12);
  EXPECT_TRUE(d.force(u, -1.0).isZero(0.0));  // no (negative) thrust, no rotor drag
  DragLaw l;
  l.lift = 0.02;
  EXPECT_LT((l.force(u, 9.81) - Vec3(0.0, 0.0, 0.02 * 5.0)).norm(), 1e-12);
}

// The law's residual sigma enters the dynamics factor's covariance as one body-frame error held
// over the interval: on a short, nearly straight interval the beta block is ~ dt^2 sigma^2 and
// the alpha block ~ (dt^2 / 2)^2 sigma^2; without sigma nothing is added.
TEST(DragLaw, SigmaAddsAHeldErrorToTheCovariance) {
  const AnalyticFlight f;
  const auto imu = test::sampleImu(f, 1000.0, 1.0);
  std::vector<ThrustSample> thrust;
  for (const ImuSample& s : imu) thrust.push_back({s.t, f.specificForce(toSeconds(s.t))});
  const double dt = 0.02;
  const auto pit = PreintegratedThrust::integrate(imu, thrust, fromSeconds(0.5), fromSeconds(0.5 + dt),
                                                  Vec6::Zero(), ThrustNoiseParams());
  DragLaw d = vehicleDrag();
  EXPECT_TRUE(dragCovariance(pit, d, Vec3::Zero(), Vec3::Zero()).isZero(0.0));
  d.sigma = Vec3(0.6, 0.5, 1.0);
  const Mat6 C = dragCovariance(pit, d, Vec3::Zero(), Vec3::Zero());
  const Vec3 var = d.sigma.cwiseAbs2();
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(C(3 + a, 3 + a), dt * dt * var(a), 0.05 * dt * dt * var(a)) << a;
    EXPECT_NEAR(C(a, a), 0.25 * dt * dt * dt * dt * var(a), 0.05 * 0.25 * dt * dt * dt * dt * var(a)) << a;
  }
  EXPECT_LT((C - C.transpose()).norm(), 1e-15);
  d.linear.setZero(), d.rotor.setZero(), d.quadratic.setZero(), d.lift = 0.0;  // no law: no sigma either
  EXPECT_TRUE(dragCovariance(pit, d, Vec3::Zero(), Vec3::Zero()).isZero(0.0));
}

// A sigma growing with speed, body rate and thrust is evaluated per node at the given velocity
// (frame i), the node's gyro and thrust: on a short interval the beta block is ~ dt^2
// sigma(u, w, T)^2. With only a negligible varying part the per-node sum reduces to the
// closed form of the constant sigma.
TEST(DragLaw, SigmaGrowsWithTheSpeedItIsEvaluatedAt) {
  const AnalyticFlight f;
  const auto imu = test::sampleImu(f, 1000.0, 1.0);
  std::vector<ThrustSample> thrust;
  for (const ImuSample& s : imu) thrust.push_back({s.t, f.specificForce(toSeconds(s.t))});
  const double dt = 0.02, t_i = 0.5;
  const auto pit = PreintegratedThrust::integrate(imu, thrust, fromSeconds(t_i), fromSeconds(t_i + dt),
                                                  Vec6::Zero(), ThrustNoiseParams());
  DragLaw d = vehicleDrag();
  d.sigma = Vec3(0.6, 0.5, 1.0);
  const Mat6 constant = dragCovariance(pit, d, Vec3::Zero(), Vec3::Zero());
  d.sigma_rate = Vec3::Constant(1e-200);
  EXPECT_LT((dragCovariance(pit, d, Vec3::Zero(), Vec3::Zero()) - constant).norm(), 1e-12 * constant.norm());

  d.sigma_rate.setZero();
  d.sigma_speed = Vec3(0.1, 0.05, 0.2);
  d.sigma_thrust = Vec3(0.0, 0.0, 0.03);
  const Vec3 u(10.0, -4.0, 1.0);
  const Mat6 C = dragCovariance(pit, d, u, u);
  const Vec3 w = f.gyro(t_i);
  const Vec3 var = d.sigmaAt(u, w, f.specificForce(t_i).norm()).cwiseAbs2();
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(C(3 + a, 3 + a), dt * dt * var(a), 0.05 * dt * dt * var(a)) << a;
    EXPECT_GT(C(3 + a, 3 + a), 1.5 * constant(3 + a, 3 + a)) << a;
  }
}

}  // namespace
}  // namespace hdvio
