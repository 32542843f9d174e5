#include "hdvio/learned/force_model_error.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hdvio::learned {

std::vector<Vec3> forceModelError(const FlightSamples& flight, const Tcn* network, const DragLaw& law) {
  if (flight.force.size() != flight.size())
    throw std::invalid_argument(flight.name + ": no measured force to compare the model with");
  MatrixXf learned;
  std::size_t first = 0;
  if (network) {
    MatrixXf x(6, static_cast<long>(flight.size()));
    for (std::size_t k = 0; k < flight.size(); ++k) {
      x.col(static_cast<long>(k)).head<3>() = flight.thrust[k].cast<float>();
      x.col(static_cast<long>(k)).tail<3>() = flight.gyro[k].cast<float>();
    }
    learned = network->forwardSequence(x);
    first = static_cast<std::size_t>(network->architecture().window - 1);
  }
  std::vector<Vec3> error;
  for (std::size_t k = first; k < flight.size(); ++k) {
    Vec3 model = flight.thrust[k] + law.force(flight.q_WB[k].conjugate() * flight.v_W[k], flight.thrust[k].norm());
    if (network) model += learned.col(static_cast<long>(k)).head<3>().cast<double>();
    error.push_back(flight.force[k] - model);
  }
  return error;
}

double modelErrorWalk(const std::vector<std::vector<Vec3>>& series, double rate_hz, double block_s) {
  if (!(rate_hz > 0.0) || !(block_s > 0.0)) throw std::invalid_argument("modelErrorWalk: rate and block must be positive");
  const auto n = static_cast<std::size_t>(std::max(1L, std::lround(block_s * rate_hz)));
  const double span = static_cast<double>(n) / rate_hz;
  double excess = 0.0, weight = 0.0;
  for (const std::vector<Vec3>& e : series) {
    const std::size_t blocks = e.size() / n;
    if (blocks < 2 || e.size() < 2) continue;
    Vec3 white = Vec3::Zero();  // per-sample white variance, per axis
    for (std::size_t k = 1; k < e.size(); ++k) white += 0.5 * (e[k] - e[k - 1]).cwiseAbs2();
    white /= static_cast<double>(e.size() - 1);
    std::vector<Vec3> mean(blocks, Vec3::Zero());
    for (std::size_t b = 0; b < blocks; ++b) {
      for (std::size_t k = b * n; k < (b + 1) * n; ++k) mean[b] += e[k];
      mean[b] /= static_cast<double>(n);
    }
    for (std::size_t b = 1; b < blocks; ++b) {
      excess += (mean[b] - mean[b - 1]).squaredNorm() - white.sum() * 2.0 / static_cast<double>(n);
      weight += 2.0 * span;  // (T_a + T_b) / 3 per axis, summed over the three axes
    }
  }
  return weight > 0.0 ? std::sqrt(std::max(excess / weight, 0.0)) : 0.0;
}

}  // namespace hdvio::learned
