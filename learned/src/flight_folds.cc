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

}  // namespace hdvio::learned
