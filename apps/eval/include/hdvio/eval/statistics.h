#pragma once
// Summary statistics of an error array, computed the way evo and the rpg toolbox do (numpy:
// population std, median averaging the two middle values).
#include <cstddef>
#include <vector>

namespace hdvio::eval {

struct ErrorStatistics {
  std::size_t count = 0;
  double rmse = 0.0, mean = 0.0, median = 0.0, std = 0.0, min = 0.0, max = 0.0, sse = 0.0;
};

// All fields are NaN (count 0) for an empty array.
ErrorStatistics computeStatistics(const std::vector<double>& errors);

}  // namespace hdvio::eval
