// The drag law on real flights (NeuroBEM, through HDVIO_DATA_DIR): the fold that holds out the
// fastest flight (figure8_4), fitted on the other three as hdvio_drag_lofo does. The rotor +
// quadratic + lift law chosen on the folds must beat the linear + quadratic law there and stay
// within 2x the NeuroBEM model (docs/learned.md: 2.028 vs 2.516 N, NeuroBEM 1.197 N).
#include <gtest/gtest.h>

#include <filesystem>

#include "hdvio/learned/force_metrics.h"
#include "hdvio/learned/thrust_identification.h"
#include "hdvio/train/drag_law_fit.h"
#include "hdvio/train/flight_loading.h"
#include "hdvio/train/training_config.h"

namespace hdvio {
namespace {

constexpr double kMass = 0.772;

TEST(DragLawNeuroBem, RotorAndLiftTermsWinOnTheFastestHeldOutFlight) {
  const std::string root = std::string(HDVIO_DATA_DIR);
  const std::vector<std::string> train_flights = {"neurobem/figure8_1_bemnn20210218170320seg2.csv",
                                                  "neurobem/figure8_2_bemnn20210223104803seg2.csv",
                                                  "neurobem/race_track_2_bemnn20210218172600seg1.csv"};
  const std::string test_flight = "neurobem/figure8_4_bemnn20210223172724seg2.csv";
  if (!std::filesystem::exists(root + "/" + test_flight)) GTEST_SKIP() << "missing " << root << "/" << test_flight;
  train::FlightSource source;
  source.data_root = root;
  std::vector<Sequence> sequences;
  for (const auto& p : train_flights) sequences.push_back(train::loadSequence(p, source));
  source.thrust_coefficient = learned::fitThrustJointly(sequences).thrustCoefficient(kMass);
  source.mass = kMass;
  std::vector<learned::FlightSamples> blocks, left_out;
  for (const auto& p : train_flights) train::splitIntoBlocks(train::loadFlight(p, source), 500, 6, &blocks, &left_out);
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

}  // namespace
}  // namespace hdvio
