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

TEST(FlightFolds, ContiguousBlocksTileTheFlightAndKeepTheGapFromTheTestBlock) {
  const std::size_t n = 9103, gap = 50;
  std::size_t tested = 0;
  for (int i = 0; i < 4; ++i) {
    const BlockFold f = contiguousBlockFold(n, 4, i, gap);
    EXPECT_EQ(f.test.begin, tested);  // consecutive blocks cover [0, n) once
    tested = f.test.end;
    std::size_t trained = 0;
    for (const SampleRange& r : f.train) {
      EXPECT_LT(r.begin, r.end);
      // Every training sample is at least `gap` samples away from the test block.
      EXPECT_TRUE(r.end + gap <= f.test.begin || r.begin >= f.test.end + gap);
      trained += r.end - r.begin;
    }
    const std::size_t cut = (i == 0 || i == 3) ? gap : 2 * gap;  // outer blocks lose one side
    EXPECT_EQ(trained + (f.test.end - f.test.begin) + cut, n);
    EXPECT_EQ(f.train.size(), (i == 0 || i == 3) ? 1u : 2u);
  }
  EXPECT_EQ(tested, n);
  EXPECT_THROW(contiguousBlockFold(n, 1, 0, gap), std::invalid_argument);
  EXPECT_THROW(contiguousBlockFold(n, 4, 4, gap), std::invalid_argument);
  EXPECT_THROW(contiguousBlockFold(n, 4, -1, gap), std::invalid_argument);
  EXPECT_THROW(contiguousBlockFold(200, 4, 0, gap), std::invalid_argument);
}

}  // namespace
}  // namespace hdvio::learned
