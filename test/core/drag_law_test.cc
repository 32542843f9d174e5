// The drag law's least-squares fit (core/drag_law.h): it recovers known coefficients from
// synthetic samples whose thrust varies (so the rotor term is separable from the constant
// linear one), keeps coefficients non-negative, and leaves terms it may not use at zero.
#include <gtest/gtest.h>

#include <random>

#include "hdvio/core/drag_law.h"

namespace hdvio {
namespace {

struct Samples {
  std::vector<Vec3> u, f;
  std::vector<double> thrust;
};

Samples synthetic(const DragLaw& truth, double noise, int n = 4000) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> speed(-12.0, 12.0), thrust(3.0, 40.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Samples s;
  for (int k = 0; k < n; ++k) {
    const Vec3 u(speed(rng), speed(rng), 0.3 * speed(rng));
    const double T = thrust(rng);
    s.u.push_back(u);
    s.thrust.push_back(T);
    s.f.push_back(truth.force(u, T) + noise * Vec3(gauss(rng), gauss(rng), gauss(rng)));
  }
  return s;
}

DragLaw physicalLaw() {
  DragLaw d;
  d.linear = Vec3(0.05, 0.0, 0.12);
  d.rotor = Vec3(0.24, 0.19, 0.07);
  d.quadratic = Vec3(0.0, 0.011, 0.047);
  d.lift = 0.016;
  return d;
}

TEST(DragLawFit, RecoversAllFourTerms) {
  const DragLaw truth = physicalLaw();
  const Samples s = synthetic(truth, 0.05);
  const DragLaw fit = fitDragLaw(s.u, s.thrust, s.f, DragTerms{true, true, true, true});
  EXPECT_LT((fit.linear - truth.linear).cwiseAbs().maxCoeff(), 5e-3) << fit.linear.transpose();
  EXPECT_LT((fit.rotor - truth.rotor).cwiseAbs().maxCoeff(), 5e-3) << fit.rotor.transpose();
  EXPECT_LT((fit.quadratic - truth.quadratic).cwiseAbs().maxCoeff(), 5e-4) << fit.quadratic.transpose();
  EXPECT_NEAR(fit.lift, truth.lift, 5e-4);
}

TEST(DragLawFit, TermsNotChosenStayZeroAndTheOthersAbsorbWhatTheyCan) {
  const DragLaw truth = physicalLaw();
  const Samples s = synthetic(truth, 0.0);
  const DragLaw lq = fitDragLaw(s.u, {}, s.f);  // the default: linear + quadratic, no thrust needed
  EXPECT_TRUE(lq.rotor.isZero(0.0));
  EXPECT_EQ(lq.lift, 0.0);
  // The rotor term at the mean sqrt(T / T_hover) (~1.4 here) goes into the linear one.
  EXPECT_GT(lq.linear.x(), truth.linear.x() + 0.2);
  const DragLaw rq = fitDragLaw(s.u, s.thrust, s.f, DragTerms{false, true, true, false});
  EXPECT_TRUE(rq.linear.isZero(0.0));
  EXPECT_NEAR(rq.rotor.y(), truth.rotor.y(), 1e-9);  // y has no linear term: exact
}

TEST(DragLawFit, CoefficientsStayNonNegative) {
  DragLaw pushing;  // an unphysical "negative drag" on x: the fit must clamp it to zero
  pushing.linear = Vec3(-0.2, 0.3, 0.1);
  pushing.rotor = Vec3(0.1, 0.1, 0.1);
  const Samples s = synthetic(pushing, 0.0);
  const DragLaw fit = fitDragLaw(s.u, s.thrust, s.f, DragTerms{true, true, true, true});
  EXPECT_GE(fit.linear.minCoeff(), 0.0);
  EXPECT_GE(fit.rotor.minCoeff(), 0.0);
  EXPECT_GE(fit.quadratic.minCoeff(), 0.0);
  EXPECT_GE(fit.lift, 0.0);
  EXPECT_EQ(fit.linear.x(), 0.0);
  EXPECT_NEAR(fit.linear.y(), 0.3, 1e-9);
}

TEST(DragLawFit, RefusesTooFewSamplesMissingThrustOrNoTerm) {
  const Samples s = synthetic(physicalLaw(), 0.0, 200);
  const std::vector<Vec3> few(s.u.begin(), s.u.begin() + 99);
  EXPECT_THROW(fitDragLaw(few, {}, few), std::invalid_argument);
  EXPECT_THROW(fitDragLaw(s.u, {}, s.f, DragTerms{false, true, false, false}), std::invalid_argument);
  EXPECT_THROW(fitDragLaw(s.u, s.thrust, s.f, DragTerms{false, false, false, false}), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio
