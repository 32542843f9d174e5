#include <gtest/gtest.h>

#include "hdvio/learned/flight_folds.h"

namespace hdvio::learned {
namespace {

TEST(FlightFolds, EachFlightIsTestedOnceAndNeverTrainedOnInItsFold) {
  const std::vector<std::string> flights{"a.csv", "b.csv", "c.csv", "d.csv"};
  std::vector<std::string> tested;
  for (int i = 0; i < 4; ++i) {
    const FlightFold f = leaveOneFlightOut(flights, i);
    EXPECT_EQ(f.test, flights[i]);
    ASSERT_EQ(f.train.size(), 3u);
    for (const auto& t : f.train) EXPECT_NE(t, f.test);
    tested.push_back(f.test);
  }
  EXPECT_EQ(tested, flights);
  // Training flights keep their order.
  EXPECT_EQ(leaveOneFlightOut(flights, 1).train, (std::vector<std::string>{"a.csv", "c.csv", "d.csv"}));
  EXPECT_EQ(leaveOneFlightOut({"x", "y"}, 0).train, std::vector<std::string>{"y"});
}

TEST(FlightFolds, RejectsBadFoldsAndLists) {
  const std::vector<std::string> flights{"a", "b", "c"};
  EXPECT_THROW(leaveOneFlightOut(flights, -1), std::invalid_argument);
  EXPECT_THROW(leaveOneFlightOut(flights, 3), std::invalid_argument);
  EXPECT_THROW(leaveOneFlightOut({"a"}, 0), std::invalid_argument);
  EXPECT_THROW(leaveOneFlightOut({"a", "b", "a"}, 1), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio::learned
