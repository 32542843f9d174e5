#pragma once
// Leave-one-flight-out folds: fold i trains on every flight but the i-th and tests on the i-th,
// so each flight is unseen exactly once and the folds decide the model choice.
#include <string>
#include <vector>

namespace hdvio::learned {

struct FlightFold {
  std::vector<std::string> train;  // in the given order, without the test flight
  std::string test;
};

// Throws std::invalid_argument for fewer than two flights, a repeated flight or a fold
// index outside [0, flights.size()).
FlightFold leaveOneFlightOut(const std::vector<std::string>& flights, int fold);

}  // namespace hdvio::learned
