// The drag law on real flights (NeuroBEM, through HDVIO_DATA_DIR): the fold that holds out the
// fastest flight (figure8_4), fitted on the other three as hdvio_drag_lofo does. The rotor +
// quadratic + lift law chosen on the folds must beat the linear + quadratic law there and stay
// within 2x the NeuroBEM model (docs/learned.md: 2.028 vs 2.516 N, NeuroBEM 1.197 N).
#include <gtest/gtest.h>

#include <filesystem>

#include "hdvio/learned/force_metrics.h"
#include "hdvio/learned/thrust_identification.h"
#include "hdvio/train/drag_law_fit.h"
#include "hdvio/train/dynamics_nis.h"
#include "hdvio/train/flight_loading.h"
#include "hdvio/train/training_config.h"

namespace hdvio {
namespace {

constexpr double kMass = 0.772;
const char* const kTestFlight = "neurobem/figure8_4_bemnn20210223172724seg2.csv";

// The fold that holds out figure8_4: C_T refit on the other three flights, their training blocks
// (every 6th 5-s block left out, as hdvio_drag_lofo), the source that loads the held-out flight.
struct Fold {
  train::FlightSource source;
  std::vector<learned::FlightSamples> blocks;
};

Fold figure8_4Fold(const std::string& root) {
  const std::vector<std::string> train_flights = {"neurobem/figure8_1_bemnn20210218170320seg2.csv",
                                                  "neurobem/figure8_2_bemnn20210223104803seg2.csv",
                                                  "neurobem/race_track_2_bemnn20210218172600seg1.csv"};
  Fold fold;
  fold.source.data_root = root;
  std::vector<Sequence> sequences;
  for (const auto& p : train_flights) sequences.push_back(train::loadSequence(p, fold.source));
  fold.source.thrust_coefficient = learned::fitThrustJointly(sequences).thrustCoefficient(kMass);
  fold.source.mass = kMass;
  std::vector<learned::FlightSamples> left_out;
  for (const auto& p : train_flights)
    train::splitIntoBlocks(train::loadFlight(p, fold.source), 500, 6, &fold.blocks, &left_out);
  return fold;
}

class DragLawNeuroBem : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string root = std::string(HDVIO_DATA_DIR);
    if (!std::filesystem::exists(root + "/" + kTestFlight)) GTEST_SKIP() << "missing " << root << "/" << kTestFlight;
    fold_ = figure8_4Fold(root);
  }
  Fold fold_;
};

TEST_F(DragLawNeuroBem, RotorAndLiftTermsWinOnTheFastestHeldOutFlight) {
  const std::string test_flight = kTestFlight;
  const train::FlightSource& source = fold_.source;
  const std::vector<learned::FlightSamples>& blocks = fold_.blocks;
  const DragLaw old_law = train::fitDragLawOn(blocks, DragTerms{true, false, true, false});
  const DragLaw new_law = train::fitDragLawOn(blocks, DragTerms{false, true, true, true});
  EXPECT_GT(new_law.rotor.x(), 0.1);
  EXPECT_GT(new_law.lift, 0.005);

  const learned::FlightSamples f = train::loadFlight(test_flight, source);
  const double thrust = learned::forceRmse(f.thrust, f.force, kMass).f;
  const double old_f = learned::forceRmse(train::thrustPlusLaw(f, old_law), f.force, kMass).f;
  const double new_f = learned::forceRmse(train::thrustPlusLaw(f, new_law), f.force, kMass).f;
  const double neurobem = learned::forceRmse(train::neuroBemForcesAt(test_flight, source, f.t, kMass), f.force, kMass).f;
  std::printf("figure8_4 held out: F thrust %.4f, linear+quadratic %.4f, rotor+quadratic+lift %.4f, NeuroBEM %.4f N\n",
              thrust, old_f, new_f, neurobem);
  EXPECT_LT(new_f, 0.9 * old_f);
  EXPECT_LT(new_f, 2.0 * neurobem);
  EXPECT_LT(old_f, thrust);
}

// The law's sigma on the same fold (docs/learned.md "The law's uncertainty"): a constant sigma
// from the three slower flights is far too narrow on the fastest one (45 % within 1 sigma); the
// sigma that grows with speed, body rate and thrust, fitted by likelihood on the same blocks,
// covers 60-80 % / 85-99 % there and has the lower held-out NLL; the dynamics factor weighted by
// it has a normalized residual of about 1 per dof there.
TEST_F(DragLawNeuroBem, SigmaThatGrowsIsCalibratedOnTheFastestHeldOutFlight) {
  const std::string test_flight = kTestFlight;
  const train::FlightSource& source = fold_.source;
  const std::vector<learned::FlightSamples>& blocks = fold_.blocks;
  const DragTerms terms{false, true, true, true};
  const DragLaw constant = train::fitDragLawOn(blocks, terms);
  const DragLaw growing = train::fitDragLawOn(blocks, terms, DragSigmaTerms{true, true, true});
  EXPECT_EQ(growing.rotor, constant.rotor);  // the sigma does not change the law

  const learned::FlightSamples f = train::loadFlight(test_flight, source);
  const std::vector<Vec3> pred = train::thrustPlusLaw(f, growing);
  const learned::SigmaCoverage c0 =
      learned::sigmaCoverage(pred, std::vector<Vec3>(f.size(), constant.sigma), f.force);
  const learned::SigmaCoverage c1 = learned::sigmaCoverage(pred, train::lawSigma(f, growing), f.force);
  std::printf("figure8_4 held out: within 1 / 2 sigma constant %.3f / %.3f (NLL %.3f), growing %.3f / %.3f (NLL %.3f)\n",
              c0.within_1_sigma, c0.within_2_sigma, c0.mean_nll, c1.within_1_sigma, c1.within_2_sigma, c1.mean_nll);
  EXPECT_LT(c0.within_1_sigma, 0.55);
  EXPECT_GT(c1.within_1_sigma, 0.60);
  EXPECT_LT(c1.within_1_sigma, 0.80);
  EXPECT_GT(c1.within_2_sigma, 0.85);
  EXPECT_LT(c1.within_2_sigma, 0.99);
  EXPECT_LT(c1.mean_nll, c0.mean_nll - 1.0);

  // The dynamics factor weighted by it (0.1-s intervals at the recorded states): the velocity
  // block's normalized residual is ~1 per dof, with the constant sigma ~4 (overconfident).
  ThrustNoiseParams noise;
  noise.thrust_noise_density = Vec3::Constant(0.01);
  const train::DynamicsNis n0 = train::dynamicsNis(f, constant, 10, noise);
  const train::DynamicsNis n1 = train::dynamicsNis(f, growing, 10, noise);
  std::printf("figure8_4 held out: dynamics factor NIS / dof (alpha, beta) constant %.2f, %.2f, growing %.2f, %.2f\n",
              n0.alpha, n0.beta, n1.alpha, n1.beta);
  EXPECT_GT(n0.beta, 3.0);
  EXPECT_GT(n1.beta, 0.6);
  EXPECT_LT(n1.beta, 1.4);
  EXPECT_LT(n1.alpha, 1.4);
}

}  // namespace
}  // namespace hdvio
