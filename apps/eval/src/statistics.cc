#include "hdvio/eval/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hdvio::eval {

ErrorStatistics computeStatistics(const std::vector<double>& errors) {
  ErrorStatistics s;
  s.count = errors.size();
  if (errors.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s.rmse = s.mean = s.median = s.std = s.min = s.max = s.sse = nan;
    return s;
  }
  const double n = static_cast<double>(errors.size());
  double sum = 0.0, sse = 0.0;
  for (double e : errors) {
    sum += e;
    sse += e * e;
  }
  s.mean = sum / n;
  s.sse = sse;
  s.rmse = std::sqrt(sse / n);
  double var = 0.0;
  for (double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(var / n);
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  s.min = sorted.front();
  s.max = sorted.back();
  const std::size_t mid = sorted.size() / 2;
  s.median = sorted.size() % 2 == 1 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  return s;
}

}  // namespace hdvio::eval
