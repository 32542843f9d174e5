#pragma once
// Everything a simulated flight depends on. Filled from YAML by loadSimConfig (strict keys:
// unknown keys and out-of-range values are InputErrors naming file, line and key path).
// See docs/simulator.md for the meaning and units of each key.
#include <cstdint>
#include <string>
#include <vector>

#include "hdvio/core/config.h"
#include "hdvio/core/lie.h"
#include "hdvio/core/sequence.h"

namespace hdvio::sim {

struct GateConfig {
  Vec3 position = Vec3::Zero();  // gate centre, world
  double yaw = 0.0;  // rad, gate normal; set from the flight direction through the gate
};

enum class TrajectoryType { kHover, kCircle, kLemniscate, kRandom, kRace };
std::string toString(TrajectoryType type);  // the YAML name

struct TrajectoryConfig {
  TrajectoryType type = TrajectoryType::kCircle;
  Vec3 center = Vec3(0.0, 0.0, 1.5);
  double max_speed = 2.0;       // m/s, peak speed reached after the ramp (ignored by hover)
  double ramp_time = 2.0;       // s, smooth start from (almost) rest
  double radius = 2.0;          // circle
  double height_amplitude = 0;  // circle / lemniscate: vertical oscillation (m)
  Vec3 extent = Vec3(2.0, 1.5, 0.5);  // lemniscate (x, y) / random (x, y, z) half sizes (m)
  int random_features = 32;     // random: Fourier features of the Gaussian process
  std::vector<GateConfig> gates;  // race: closed loop through the gate centres, in order
};

enum class YawMode { kFixed, kRate, kOscillate, kForward };

struct YawConfig {
  YawMode mode = YawMode::kFixed;
  double value = 0.0;          // rad, initial / constant yaw
  double rate = 0.0;           // rad/s (rate)
  double amplitude = 0.0;      // rad (oscillate)
  double frequency = 0.2;      // Hz (oscillate)
};

struct VehicleConfig {
  double mass = 0.8;                 // kg
  double thrust_coefficient = 1.5e-6;  // N s^2 rad^-2 (per rotor)
  double torque_coefficient = 0.016;   // m, yaw torque per newton of rotor thrust
  double arm_length = 0.15;          // m, rotor distance from the centre (X layout)
  Vec3 inertia = Vec3(0.0025, 0.0021, 0.0043);  // kg m^2, diagonal
  Vec3 rotor_drag = Vec3(0.3, 0.3, 0.05);       // 1/s, linear in body airspeed
  double fuselage_drag = 0.01;                  // 1/m, quadratic in airspeed
  // What the thrust channel writes: the rotors' thrust (measured) or the controller's command,
  // which leads it by the lag (commanded).
  enum class ThrustOutput { kMeasured, kCommanded } thrust_output = ThrustOutput::kMeasured;
  double thrust_scale = 1.0;   // written thrust = scale * true (+ lag) + bias
  double thrust_bias = 0.0;    // m/s^2
  double thrust_lag = 0.0;     // s, first-order actuation lag (commanded output leads)
  double thrust_noise = 0.0;   // m/s^2 std of white noise on the written thrust
};

struct JetConfig {
  Vec3 origin = Vec3::Zero();
  Vec3 direction = Vec3::UnitX();  // normalized on load
  double speed = 3.0;              // m/s on the axis near the fan
  double radius = 0.5;             // m, Gaussian cross-section
  double length = 5.0;             // m, Gaussian decay along the axis
};

struct WindConfig {
  Vec3 steady = Vec3::Zero();  // m/s, world
  std::vector<JetConfig> jets;
  double gust_std = 0.0;       // m/s per horizontal axis (vertical: half)
  double gust_time_scale = 2.0;  // s, correlation time of gusts
};

struct ForceEventConfig {
  enum class Type { kPull, kPayload } type = Type::kPull;
  double start = 0.0;         // s
  double end = 1e9;           // s (payload: release)
  double ramp = 0.3;          // s, rise/fall time
  Vec3 force = Vec3::Zero();  // pull: mass-normalized world force (m/s^2)
  double mass = 0.0;          // payload: kg
};

struct ImuSimConfig {
  double rate_hz = 200.0;
  double gyro_noise_density = 1.6968e-4;   // rad/s/sqrt(Hz) (EuRoC values)
  double gyro_random_walk = 1.9393e-5;     // rad/s^2/sqrt(Hz)
  double accel_noise_density = 2.0e-3;     // m/s^2/sqrt(Hz)
  double accel_random_walk = 3.0e-3;       // m/s^3/sqrt(Hz)
  bool noise = true;                       // false: exact signals, biases constant
  Vec3 initial_gyro_bias = Vec3::Zero();
  Vec3 initial_accel_bias = Vec3::Zero();
};

struct CameraSimConfig {
  bool enabled = true;
  int width = 752, height = 480;
  double rate_hz = 20.0;
  double fu = 458.0, fv = 458.0, cu = 376.0, cv = 240.0;
  DistortionModel distortion = DistortionModel::kNone;
  std::vector<double> distortion_coefficients;  // k1 k2 p1 p2
  Pose T_BS = defaultCameraMount();             // camera -> body
  double noise_std = 0.0;            // gray levels
  double exposure_variation = 0.0;   // relative amplitude of a slow gain change
  double exposure_period = 10.0;     // s
  int motion_blur_samples = 1;       // >1: average sub-frames over the exposure time
  double exposure_time = 0.005;      // s
  int png_compression = 1;           // 0..9

  // Forward-looking camera: optical axis along body x, image right = body -y, down = body -z.
  static Pose defaultCameraMount();
};

struct SceneConfig {
  Vec3 room_min = Vec3(-5.0, -4.0, 0.0);
  Vec3 room_max = Vec3(5.0, 4.0, 4.0);
  double texel_size = 0.01;       // m per texel at the finest level
  bool render_gates = true;       // race gates as solid frames in the images
  double gate_inner_size = 1.5;   // m
  double gate_border = 0.2;       // m
  int num_landmarks = 0;          // ground-truth points on the walls
  double min_clearance = 0.3;     // m, required distance of the flight from the walls
};

// Race flights: pixel detections of the gates' inner corners (docs/gate_io.md).
struct GateDetectionConfig {
  bool enabled = true;         // write gates0/ and gate_corners0/ when the scene has gates
  double pixel_noise = 1.0;    // px, std of white Gaussian noise per image coordinate
  double max_distance = 30.0;  // m, corners farther from the camera are not detected
  double dropout = 0.0;        // probability that a visible corner is missed
};

struct SimConfig {
  std::string name = "sim";
  std::uint64_t seed = 1;
  double duration = 10.0;        // s
  std::int64_t start_time_ns = 1000000000;  // first timestamp
  TrajectoryConfig trajectory;
  YawConfig yaw;
  VehicleConfig vehicle;
  WindConfig wind;
  std::vector<ForceEventConfig> forces;
  ImuSimConfig imu;
  CameraSimConfig camera;
  SceneConfig scene;
  GateDetectionConfig gate_detection;
};

// Reads and validates; calls finish() on every map so unknown keys are errors.
SimConfig loadSimConfig(const ConfigReader& reader);

}  // namespace hdvio::sim
