#include "hdvio/sim/gate_detections.h"

#include <random>

namespace hdvio::sim {
namespace {

// Corner signs (gate y, gate z); gate y points left of the flight direction, z up.
constexpr double kCornerSign[io::kCornersPerGate][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};

Vec3 cornerInGate(const Gate& g, int k, double inset, double front_offset) {
  const double h = g.inner_half - inset;
  return Vec3(-g.half_depth - front_offset, kCornerSign[k][0] * h, kCornerSign[k][1] * h);
}

}  // namespace

std::array<Vec3, io::kCornersPerGate> gateCornersWorld(const Gate& g) {
  std::array<Vec3, io::kCornersPerGate> out;
  for (int k = 0; k < io::kCornersPerGate; ++k) out[k] = g.center + g.R_WG * cornerInGate(g, k, 0.0, 0.0);
  return out;
}

bool gateCornerVisible(const Scene& scene, const Gate& g, int corner_id, const Vec3& camera_center) {
  const Vec3 probe = g.center + g.R_WG * cornerInGate(g, corner_id, 0.01, 0.001);
  return !scene.segmentBlocked(camera_center, probe);
}

bool mapsBackToRay(const CameraModel& camera, const Eigen::Vector2d& uv, const Vec3& p_C) {
  bool converged = false;
  const Vec3 bearing = camera.unproject(uv, &converged);
  return converged && (bearing / bearing.z() - p_C / p_C.z()).norm() <= 1e-6;
}

io::GateData detectGateCorners(const Scene& scene, const CameraModel& camera,
                               const GateDetectionConfig& config,
                               const std::vector<std::pair<Timestamp, Pose>>& frames,
                               std::uint64_t seed) {
  io::GateData out;
  const std::vector<Gate>& gates = scene.gates();
  std::vector<std::array<Vec3, io::kCornersPerGate>> corners;
  for (std::size_t i = 0; i < gates.size(); ++i) {
    corners.push_back(gateCornersWorld(gates[i]));
    for (int k = 0; k < io::kCornersPerGate; ++k) out.corners[{static_cast<int>(i), k}] = corners[i][k];
  }
  // Own stream: the other outputs of a flight do not change with the detection settings.
  std::mt19937_64 rng(seed * 2654435761ULL + 3);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const auto& [t, T_WC] : frames) {
    const Pose T_CW = T_WC.inverse();
    for (std::size_t i = 0; i < gates.size(); ++i) {
      for (int k = 0; k < io::kCornersPerGate; ++k) {
        const Vec3 p_C = T_CW * corners[i][k];
        if (p_C.norm() > config.max_distance) continue;
        Eigen::Vector2d uv;
        if (!camera.project(p_C, &uv) || !camera.inImage(uv)) continue;
        if (!mapsBackToRay(camera, uv, p_C)) continue;
        if (!gateCornerVisible(scene, gates[i], k, T_WC.p)) continue;
        const bool dropped = unit(rng) < config.dropout;
        const Eigen::Vector2d noise(normal(rng), normal(rng));
        if (dropped) continue;
        uv += config.pixel_noise * noise;
        out.detections.push_back({t, static_cast<int>(i), k, uv.x(), uv.y()});
      }
    }
  }
  return out;
}

}  // namespace hdvio::sim
