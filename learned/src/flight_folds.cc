#include "hdvio/learned/flight_folds.h"

#include <set>
#include <stdexcept>

namespace hdvio::learned {

FlightFold leaveOneFlightOut(const std::vector<std::string>& flights, int fold) {
  if (flights.size() < 2) throw std::invalid_argument("leave-one-flight-out needs at least two flights");
  if (std::set<std::string>(flights.begin(), flights.end()).size() != flights.size())
    throw std::invalid_argument("leave-one-flight-out: a flight is listed twice");
  if (fold < 0 || static_cast<std::size_t>(fold) >= flights.size())
    throw std::invalid_argument("fold " + std::to_string(fold) + " outside [0, " +
                                std::to_string(flights.size()) + ")");
  FlightFold f;
  for (std::size_t i = 0; i < flights.size(); ++i) {
    if (static_cast<int>(i) == fold) f.test = flights[i];
    else f.train.push_back(flights[i]);
  }
  return f;
}

BlockFold contiguousBlockFold(std::size_t samples, int folds, int fold, std::size_t gap) {
  if (folds < 2) throw std::invalid_argument("block cross-validation needs at least two folds");
  if (fold < 0 || fold >= folds)
    throw std::invalid_argument("fold " + std::to_string(fold) + " outside [0, " + std::to_string(folds) + ")");
  const auto k = static_cast<std::size_t>(folds);
  if (samples / k < gap + 1)
    throw std::invalid_argument("blocks of " + std::to_string(samples / k) + " samples are not longer than the gap");
  const auto i = static_cast<std::size_t>(fold);
  BlockFold f;
  f.test = {i * samples / k, (i + 1) * samples / k};
  if (f.test.begin > gap) f.train.push_back({0, f.test.begin - gap});
  if (f.test.end + gap < samples) f.train.push_back({f.test.end + gap, samples});
  return f;
}

}  // namespace hdvio::learned
