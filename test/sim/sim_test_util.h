#pragma once
// Shared helpers for the simulator tests: small scenarios built in code.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "hdvio/sim/sim_config.h"

namespace hdvio::sim::testing {

// An aggressive inertial-only flight: random GP path at 6 m/s in a hall, drag, steady wind,
// a fan jet, gusts, a rope pull and a payload; exact (noise-free) IMU.
inline SimConfig aggressiveInertialConfig(double duration = 10.0) {
  SimConfig c;
  c.seed = 3;
  c.duration = duration;
  c.trajectory.type = TrajectoryType::kRandom;
  c.trajectory.center = Vec3(0.0, 0.0, 3.0);
  c.trajectory.extent = Vec3(6.0, 4.0, 1.5);
  c.trajectory.max_speed = 6.0;
  c.trajectory.ramp_time = 1.0;
  c.yaw.mode = YawMode::kRate;
  c.yaw.rate = 0.5;
  c.scene.room_min = Vec3(-10.0, -8.0, 0.0);
  c.scene.room_max = Vec3(10.0, 8.0, 6.0);
  c.wind.steady = Vec3(2.0, -1.0, 0.0);
  c.wind.gust_std = 1.0;
  c.wind.gust_time_scale = 1.5;
  JetConfig jet;
  jet.origin = Vec3(-6.0, 0.0, 3.0);
  jet.direction = Vec3(1.0, 0.0, 0.0);
  jet.speed = 4.0;
  jet.radius = 1.5;
  jet.length = 8.0;
  c.wind.jets.push_back(jet);
  ForceEventConfig pull;
  pull.type = ForceEventConfig::Type::kPull;
  pull.start = 2.0;
  pull.end = 4.0;
  pull.ramp = 0.4;
  pull.force = Vec3(2.0, 0.0, -1.0);
  c.forces.push_back(pull);
  ForceEventConfig payload;
  payload.type = ForceEventConfig::Type::kPayload;
  payload.start = 5.0;
  payload.end = 8.0;
  payload.ramp = 0.5;
  payload.mass = 0.2;
  c.forces.push_back(payload);
  c.imu.noise = false;
  c.camera.enabled = false;
  return c;
}

// A race track through six gates in a 44 x 30 m hall at 15 m/s peak, heading forward.
inline SimConfig raceConfig(double duration = 12.0) {
  SimConfig c;
  c.duration = duration;
  c.trajectory.type = TrajectoryType::kRace;
  c.trajectory.max_speed = 15.0;
  c.trajectory.ramp_time = 3.0;
  for (const Vec3& g : {Vec3(15, 0, 2.5), Vec3(8, 9, 3.5), Vec3(-8, 9, 2.5), Vec3(-15, 0, 3.5),
                        Vec3(-8, -9, 2.5), Vec3(8, -9, 3.5)}) {
    GateConfig gate;
    gate.position = g;
    c.trajectory.gates.push_back(gate);
  }
  c.yaw.mode = YawMode::kForward;
  c.scene.room_min = Vec3(-22, -15, 0);
  c.scene.room_max = Vec3(22, 15, 8);
  c.wind.steady = Vec3(0.0, 3.0, 0.0);
  c.imu.noise = false;
  c.camera.enabled = false;
  return c;
}

// A small visual scenario: slow circle in a room, 160x120 images.
inline SimConfig smallVisualConfig() {
  SimConfig c;
  c.seed = 5;
  c.duration = 1.0;
  c.trajectory.type = TrajectoryType::kCircle;
  c.trajectory.radius = 1.0;
  c.trajectory.max_speed = 1.0;
  c.trajectory.ramp_time = 0.0;
  c.scene.room_min = Vec3(-3.0, -3.0, 0.0);
  c.scene.room_max = Vec3(3.0, 3.0, 3.0);
  c.scene.texel_size = 0.01;
  c.scene.num_landmarks = 600;
  c.camera.width = 160;
  c.camera.height = 120;
  c.camera.fu = c.camera.fv = 100.0;
  c.camera.cu = 80.0;
  c.camera.cv = 60.0;
  c.camera.rate_hz = 10.0;
  c.imu.noise = false;
  return c;
}

// A fresh empty directory under the system temp dir.
inline std::filesystem::path freshTempDir(const std::string& name) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() /
                                  ("hdvio_sim_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

}  // namespace hdvio::sim::testing
