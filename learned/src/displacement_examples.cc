#include "hdvio/learned/displacement_examples.h"

#include <stdexcept>

namespace hdvio::learned {
namespace {

const std::vector<Vec3>& forceChannel(const FlightSamples& f, DisplacementInputKind kind) {
  if (kind == DisplacementInputKind::kThrustGyro) return f.thrust;
  if (f.force.size() != f.size()) throw std::invalid_argument(f.name + ": no accelerometer samples");
  return f.force;
}

void requireWindow(const FlightSamples& f, std::size_t end, int window) {
  if (window < 1 || end < static_cast<std::size_t>(window) || end >= f.size()) {
    throw std::invalid_argument("window ending at sample " + std::to_string(end) + " is not inside " + f.name);
  }
}

}  // namespace

std::vector<DisplacementExample> displacementExamples(const std::vector<FlightSamples>& flights,
                                                      int window, int stride) {
  if (window < 1 || stride < 1) throw std::invalid_argument("window and stride must be positive");
  std::vector<DisplacementExample> out;
  for (std::size_t i = 0; i < flights.size(); ++i) {
    for (std::size_t end = static_cast<std::size_t>(window); end < flights[i].size();
         end += static_cast<std::size_t>(stride)) {
      out.push_back({i, end});
    }
  }
  return out;
}

MatrixXf worldWindow(const FlightSamples& f, std::size_t end, int window, DisplacementInputKind kind) {
  requireWindow(f, end, window);
  const std::vector<Vec3>& force = forceChannel(f, kind);
  MatrixXf x(6, window);
  for (int k = 0; k < window; ++k) {
    const std::size_t s = end + 1 - static_cast<std::size_t>(window) + static_cast<std::size_t>(k);
    const Mat3 R = f.q_WB[s].toRotationMatrix();
    x.block<3, 1>(0, k) = (R * force[s]).cast<float>();
    x.block<3, 1>(3, k) = (R * f.gyro[s]).cast<float>();
  }
  return x;
}

Vec3 displacementTarget(const FlightSamples& f, std::size_t end, int window) {
  requireWindow(f, end, window);
  return f.p_W[end] - f.p_W[end - static_cast<std::size_t>(window)];
}

Vec3 integratedDisplacement(const FlightSamples& f, std::size_t end, int window,
                            DisplacementInputKind kind) {
  requireWindow(f, end, window);
  const std::vector<Vec3>& force = forceChannel(f, kind);
  const double dt = 1.0 / f.rate_hz;
  Vec3 v = f.v_W[end - static_cast<std::size_t>(window)];
  Vec3 p = Vec3::Zero();
  for (std::size_t s = end + 1 - static_cast<std::size_t>(window); s <= end; ++s) {
    const Vec3 a = f.q_WB[s] * force[s] + gravityWorld();
    p += v * dt + 0.5 * a * dt * dt;
    v += a * dt;
  }
  return p;
}

}  // namespace hdvio::learned
