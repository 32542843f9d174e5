#include "hdvio/learned/training_envelope.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hdvio::learned {
namespace {
// The q-quantile by nearest rank (deterministic, no interpolation).
double quantile(std::vector<double> x, double q) {
  const long n = static_cast<long>(x.size());
  const long rank = std::clamp(static_cast<long>(std::ceil(q * n)) - 1, 0L, n - 1);
  std::nth_element(x.begin(), x.begin() + rank, x.end());
  return x[rank];
}
}  // namespace

ModelEnvelope trainingEnvelope(const std::vector<FlightSamples>& flights) {
  std::vector<double> speed, rate, thrust;
  for (const auto& f : flights) {
    for (std::size_t k = 0; k < f.size(); ++k) {
      speed.push_back(f.v_W[k].norm());
      rate.push_back(f.gyro[k].norm());
      thrust.push_back(f.thrust[k].norm());
    }
  }
  if (speed.empty()) throw std::invalid_argument("trainingEnvelope: no training samples");
  ModelEnvelope e;
  e.speed_max = quantile(speed, kEnvelopeQuantile);
  e.rate_max = quantile(rate, kEnvelopeQuantile);
  e.thrust_min = quantile(thrust, 1.0 - kEnvelopeQuantile);
  e.thrust_max = quantile(thrust, kEnvelopeQuantile);
  return e;
}

}  // namespace hdvio::learned
