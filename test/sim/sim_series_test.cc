// Taylor-series arithmetic: identities that hold for every coefficient, so any wrong
// recurrence shows up in the derivatives the simulator relies on.
#include <gtest/gtest.h>

#include "hdvio/sim/series.h"

namespace hdvio::sim {
namespace {

void expectSeriesNear(const Series& a, const Series& b, double tol, int orders = kSeriesOrder + 1) {
  for (int k = 0; k < orders; ++k) EXPECT_NEAR(a.c[k], b.c[k], tol) << "coefficient " << k;
}

// A non-trivial argument: u(t) = 0.3 + 0.7 t + 0.2 t^2 - 0.1 t^3 around t = 0.4.
Series argument() {
  const Series t = Series::variable(0.4);
  return 0.3 + 0.7 * t + 0.2 * t * t - 0.1 * t * t * t;
}

TEST(SimSeries, ElementaryIdentitiesHoldForAllCoefficients) {
  const Series u = argument();
  Series s, c;
  sincos(u, &s, &c);
  expectSeriesNear(s * s + c * c, Series(1.0), 1e-14);
  expectSeriesNear(exp(log(u)), u, 1e-14);
  expectSeriesNear(sqrt(u) * sqrt(u), u, 1e-14);
  expectSeriesNear((s / u) * u, s, 1e-14);
  expectSeriesNear(atan2(s, c), u, 1e-13);
  expectSeriesNear(atan2(-2.0 * s, -2.0 * c) + M_PI, u, 1e-13);  // other quadrant, same slope
  // d/dt logcosh(u) = tanh(u) u'  (the top order is lost by differentiation)
  expectSeriesNear(derivative(logcosh(u)), tanh(u) * derivative(u), 1e-13, kSeriesOrder);
  expectSeriesNear(derivative(logcosh(-3.0 * u)), tanh(-3.0 * u) * derivative(-3.0 * u), 1e-12, kSeriesOrder);
  // tanh(x) = (e^2x - 1) / (e^2x + 1) on both signs
  for (double scale : {1.0, -1.0}) {
    const Series e = exp(2.0 * scale * u);
    expectSeriesNear(tanh(scale * u), (e - 1.0) / (e + 1.0), 1e-14);
  }
}

TEST(SimSeries, DerivativesMatchClosedForm) {
  // f(t) = sin(t^2) at t0 = 0.8: f' = 2t cos(t^2), f'' = 2 cos(t^2) - 4 t^2 sin(t^2)
  const double t0 = 0.8;
  const Series t = Series::variable(t0);
  const Series f = sin(t * t);
  EXPECT_NEAR(f.derivative(0), std::sin(t0 * t0), 1e-15);
  EXPECT_NEAR(f.derivative(1), 2.0 * t0 * std::cos(t0 * t0), 1e-14);
  EXPECT_NEAR(f.derivative(2), 2.0 * std::cos(t0 * t0) - 4.0 * t0 * t0 * std::sin(t0 * t0), 1e-13);
  // f''' = -12 t sin(t^2) - 8 t^3 cos(t^2)
  EXPECT_NEAR(f.derivative(3), -12.0 * t0 * std::sin(t0 * t0) - 8.0 * t0 * t0 * t0 * std::cos(t0 * t0), 1e-12);
}

}  // namespace
}  // namespace hdvio::sim
