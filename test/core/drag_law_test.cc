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

// The sigma fit (withFittedSigma): residuals drawn with a known speed-, rate- and thrust-dependent
// sigma give back its coefficients, and the fitted sigma covers 68 % / 95 % of fresh draws; with
// no term it is the residual's RMS.
struct SigmaSamples {
  std::vector<Vec3> u, w, f;
  std::vector<double> thrust;
};

SigmaSamples heteroscedastic(const DragLaw& truth, unsigned seed, int n = 20000) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> speed(-10.0, 10.0), rate(-4.0, 4.0), thrust(4.0, 35.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  SigmaSamples s;
  for (int k = 0; k < n; ++k) {
    const Vec3 u(speed(rng), speed(rng), 0.3 * speed(rng)), w(rate(rng), rate(rng), rate(rng));
    const double T = thrust(rng);
    const Vec3 sigma = truth.sigmaAt(u, w, T);
    s.u.push_back(u), s.w.push_back(w), s.thrust.push_back(T);
    s.f.push_back(truth.force(u, T) + sigma.cwiseProduct(Vec3(gauss(rng), gauss(rng), gauss(rng))));
  }
  return s;
}

DragLaw lawWithGrowingSigma() {
  DragLaw d = physicalLaw();
  d.sigma = Vec3(0.2, 0.25, 0.4);
  d.sigma_speed = Vec3(0.04, 0.03, 0.08);
  d.sigma_rate = Vec3(0.1, 0.08, 0.15);
  d.sigma_thrust = Vec3(0.01, 0.01, 0.03);
  return d;
}

TEST(DragSigmaFit, RecoversASigmaThatGrowsWithSpeedRateAndThrust) {
  const DragLaw truth = lawWithGrowingSigma();
  const SigmaSamples s = heteroscedastic(truth, 3);
  DragLaw start = truth;
  start.sigma.setZero();  // the fit must not read the given sigma
  const DragLaw fit = withFittedSigma(start, s.u, s.w, s.thrust, s.f, DragSigmaTerms{true, true, true});
  const auto rel = [](const Vec3& a, const Vec3& b) { return ((a - b).cwiseQuotient(b)).cwiseAbs().maxCoeff(); };
  EXPECT_LT(rel(fit.sigma, truth.sigma), 0.25) << fit.sigma.transpose();
  EXPECT_LT(rel(fit.sigma_speed, truth.sigma_speed), 0.1) << fit.sigma_speed.transpose();
  EXPECT_LT(rel(fit.sigma_rate, truth.sigma_rate), 0.1) << fit.sigma_rate.transpose();
  EXPECT_LT(rel(fit.sigma_thrust, truth.sigma_thrust), 0.1) << fit.sigma_thrust.transpose();
  EXPECT_EQ(fit.rotor, truth.rotor);  // the law itself is untouched

  const SigmaSamples fresh = heteroscedastic(truth, 4);
  int in1 = 0, in2 = 0, n = 0;
  for (std::size_t k = 0; k < fresh.u.size(); ++k) {
    const Vec3 e = (fresh.f[k] - fit.force(fresh.u[k], fresh.thrust[k])).cwiseAbs();
    const Vec3 sigma = fit.sigmaAt(fresh.u[k], fresh.w[k], fresh.thrust[k]);
    for (int a = 0; a < 3; ++a, ++n) in1 += e(a) <= sigma(a), in2 += e(a) <= 2.0 * sigma(a);
  }
  EXPECT_NEAR(static_cast<double>(in1) / n, 0.683, 0.01);
  EXPECT_NEAR(static_cast<double>(in2) / n, 0.954, 0.01);
}

TEST(DragSigmaFit, WithoutTermsItIsTheResidualRmsAndTermsNotChosenStayZero) {
  const DragLaw truth = lawWithGrowingSigma();
  const SigmaSamples s = heteroscedastic(truth, 5, 3000);
  const DragLaw constant = withFittedSigma(truth, s.u, s.w, s.thrust, s.f);
  EXPECT_FALSE(constant.hasVaryingSigma());
  Vec3 sum_sq = Vec3::Zero();
  for (std::size_t k = 0; k < s.u.size(); ++k) sum_sq += (s.f[k] - truth.force(s.u[k], s.thrust[k])).cwiseAbs2();
  EXPECT_EQ(constant.sigma, (sum_sq / static_cast<double>(s.u.size())).cwiseSqrt());
  const DragLaw speed_only = withFittedSigma(truth, s.u, s.w, s.thrust, s.f, DragSigmaTerms{true, false, false});
  EXPECT_TRUE(speed_only.sigma_rate.isZero(0.0));
  EXPECT_TRUE(speed_only.sigma_thrust.isZero(0.0));
  EXPECT_GT(speed_only.sigma_speed.minCoeff(), 0.0);
  const std::vector<Vec3> few(s.u.begin(), s.u.begin() + 99);
  EXPECT_THROW(withFittedSigma(truth, few, few, std::vector<double>(99, 9.81), few), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio
