// The Model-EKF's thrust + linear drag model: its displacement against analytic flights that
// obey the model, its velocity and attitude Jacobians against finite differences, and the
// least-squares fit recovering known parameters.
#include <gtest/gtest.h>

#include <random>

#include "analytic_trajectory.h"
#include "hdvio/backend/imo/drag_model.h"
#include "hdvio/core/error.h"

namespace hdvio::imo {
namespace {

using testing::trajectoryAt;

const Vec3 kDrag(0.35, 0.45, 0.1);

// Thrust of the analytic flight under the model v' = R (k T - D R^T v) + g (k = 1).
std::vector<ThrustSample> modelThrust(const Vec3& drag, double rate_hz, double duration_s) {
  std::vector<ThrustSample> thrust;
  const int n = static_cast<int>(std::lround(duration_s * rate_hz));
  for (int k = 0; k <= n; ++k) {
    const double t = k / rate_hz;
    const auto s = trajectoryAt(t);
    thrust.push_back({fromSeconds(t), s.R.transpose() * (s.a - gravityWorld()) +
                                          drag.cwiseProduct(s.R.transpose() * s.v)});
  }
  return thrust;
}

DisplacementRequest requestAt(double t_end) {
  DisplacementRequest r;
  r.t_end = fromSeconds(t_end);
  r.t_begin = fromSeconds(t_end - 0.5);
  r.world_from_body = [](Timestamp t) { return Quat(trajectoryAt(toSeconds(t)).R); };
  r.velocity_begin = trajectoryAt(t_end - 0.5).v;
  return r;
}

TEST(DragModelSource, DisplacementMatchesFlightsThatObeyTheModel) {
  DragModel model;
  for (const Vec3& drag : {Vec3::Zero().eval(), kDrag}) {
    model.drag.linear = drag;
    const DisplacementSource source =
        makeDragModelSource(modelThrust(drag, 400.0, 2.0), model, 0.0025, Vec3::Constant(0.1),
                            gravityWorld(), false);
    for (const double t_end : {0.5, 1.2, 2.0}) {
      const DisplacementRequest r = requestAt(t_end);
      const auto est = source(r);
      ASSERT_TRUE(est.has_value());
      const Vec3 truth = trajectoryAt(t_end).p - trajectoryAt(t_end - 0.5).p;
      // Measurement z = p_j - p_i - C v_i: the predicted displacement is C v_i + z.
      EXPECT_LT((est->velocity_matrix * r.velocity_begin + est->z - truth).norm(), 2e-4)
          << "drag " << drag.transpose() << " t " << t_end;
      if (drag.isZero()) EXPECT_LT((est->velocity_matrix - 0.5 * Mat3::Identity()).norm(), 1e-12);
      else EXPECT_GT((est->velocity_matrix - 0.5 * Mat3::Identity()).norm(), 0.02);  // v matters
      EXPECT_TRUE(est->attitude_jacobian.isZero(0.0));
    }
    DisplacementRequest outside = requestAt(2.3);
    EXPECT_FALSE(source(outside).has_value());
  }
}

// The source integrates a model linear in v: a drag law with a quadratic term is refused.
TEST(DragModelSource, RejectsQuadraticDrag) {
  DragModel model;
  model.drag.linear = kDrag;
  model.drag.quadratic = Vec3(0.0, 0.01, 0.0);
  EXPECT_THROW(makeDragModelSource(modelThrust(kDrag, 400.0, 2.0), model, 0.0025, Vec3::Constant(0.1),
                                   gravityWorld(), false),
               std::invalid_argument);
}

TEST(DragModelSource, VelocityAndAttitudeJacobiansMatchFiniteDifferences) {
  DragModel model;
  model.drag.linear = kDrag;
  model.thrust_scale = 1.05;
  const DisplacementSource source = makeDragModelSource(
      modelThrust(kDrag, 400.0, 2.0), model, 0.005, Vec3::Constant(0.1), gravityWorld(), true);
  const DisplacementRequest r = requestAt(1.4);
  const auto est = *source(r);
  auto predicted = [&](const DisplacementRequest& q) {
    const auto e = *source(q);
    return (e.velocity_matrix * q.velocity_begin + e.z).eval();
  };
  const double eps = 1e-5;
  for (int k = 0; k < 3; ++k) {
    // Velocity of the begin clone.
    DisplacementRequest plus = r, minus = r;
    plus.velocity_begin += eps * Vec3::Unit(k);
    minus.velocity_begin -= eps * Vec3::Unit(k);
    const Vec3 dv = (predicted(plus) - predicted(minus)) / (2 * eps);
    EXPECT_LT((dv - est.velocity_matrix.col(k)).norm(), 1e-8) << "velocity column " << k;
    // Attitude of the begin clone, R_i -> R_i Exp(dtheta): the window's rotations follow it.
    const Quat R_i = r.world_from_body(r.t_begin);
    for (const double sgn : {1.0, -1.0}) {
      const Quat shift = R_i * quatExp(sgn * eps * Vec3::Unit(k)) * R_i.conjugate();
      DisplacementRequest& q = sgn > 0 ? plus : minus;
      q = r;
      q.world_from_body = [shift, r](Timestamp t) { return shift * r.world_from_body(t); };
    }
    const Vec3 dtheta = (predicted(plus) - predicted(minus)) / (2 * eps);
    EXPECT_LT((dtheta - est.attitude_jacobian.col(k)).norm(), 1e-6 * (1.0 + dtheta.norm()))
        << "attitude column " << k << ": " << dtheta.transpose() << " vs "
        << est.attitude_jacobian.col(k).transpose();
  }
  // The thrust direction dominates: about W^2/2 * |T| per rad.
  EXPECT_GT(est.attitude_jacobian.norm(), 0.5);
}

TEST(DragFit, RecoversThrustScaleAndDrag) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  const DragModel truth{0.93, DragLaw{Vec3(0.3, 0.42, 0.12), Vec3::Zero()}};
  std::vector<DragSample> samples;
  for (int k = 0; k < 5000; ++k) {
    DragSample s;
    s.R = so3Exp(Vec3(0.3 * n(rng), 0.3 * n(rng), 3.0 * n(rng)));
    s.velocity_body = Vec3(3.0 * n(rng), 3.0 * n(rng), 1.0 * n(rng));
    s.thrust = Vec3(0.0, 0.0, 10.0 + 2.0 * n(rng));
    s.specific_force = truth.thrust_scale * s.thrust - truth.drag.linear.cwiseProduct(s.velocity_body) +
                       0.3 * Vec3(n(rng), n(rng), n(rng));  // vibration
    samples.push_back(s);
  }
  const DragFit fit = fitDragModel(samples, true);
  EXPECT_NEAR(fit.model.thrust_scale, truth.thrust_scale, 2e-3);
  EXPECT_LT((fit.model.drag.linear - truth.drag.linear).norm(), 1e-2) << fit.model.drag.linear.transpose();
  EXPECT_LT(fit.rms_fitted.maxCoeff(), 0.33);
  EXPECT_GT(fit.rms_thrust_only.minCoeff(), 0.5);  // the thrust-only model misses drag and scale
  EXPECT_THROW(fitDragModel(std::vector<DragSample>(50), true), InputError);
}

}  // namespace
}  // namespace hdvio::imo
