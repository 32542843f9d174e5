#pragma once
// The in-memory form of one recorded or simulated flight, in the conventions of FORMATS.md:
// body frame = IMU frame, world z up, gravity (0, 0, -9.81), Hamilton quaternions, T_BS maps
// sensor coordinates to body coordinates. Every reader produces this; every tool consumes it.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hdvio/core/lie.h"
#include "hdvio/core/nav_state.h"
#include "hdvio/core/time.h"

namespace hdvio {

constexpr double kGravity = 9.81;
inline Vec3 gravityWorld() { return Vec3(0.0, 0.0, -kGravity); }

struct ImuSample {
  Timestamp t = 0;
  Vec3 gyro = Vec3::Zero();   // rad/s, IMU frame
  Vec3 accel = Vec3::Zero();  // specific force, m/s^2, IMU frame
};

// Mass-normalized collective thrust (m/s^2) in the IMU frame, measured or commanded.
struct ThrustSample {
  Timestamp t = 0;
  Vec3 thrust = Vec3::Zero();
};

struct RotorSample {
  Timestamp t = 0;
  Eigen::Vector4d speeds = Eigen::Vector4d::Zero();  // rad/s
};

struct GroundTruthState {
  Timestamp t = 0;
  Pose T_WB;                      // body (IMU) pose in the world
  Vec3 v_W = Vec3::Zero();        // m/s, world frame
  Vec3 gyro_bias = Vec3::Zero();  // rad/s
  Vec3 accel_bias = Vec3::Zero(); // m/s^2
  bool has_velocity = false;
  bool has_biases = false;
};

// Mass-normalized forces (m/s^2) in the IMU frame.
struct ForceSample {
  Timestamp t = 0;
  Vec3 external = Vec3::Zero();  // disturbance force (wind gusts, rope pulls, payloads)
  Vec3 drag = Vec3::Zero();      // aerodynamic drag
};

enum class DistortionModel { kNone, kRadialTangential, kEquidistant };

struct CameraCalibration {
  Pose T_BS;  // camera -> body
  int width = 0;
  int height = 0;
  double rate_hz = 0.0;
  double fu = 0.0, fv = 0.0, cu = 0.0, cv = 0.0;
  DistortionModel distortion = DistortionModel::kNone;
  std::vector<double> distortion_coefficients;  // radtan: k1 k2 p1 p2; equidistant: k1..k4
  std::string file;  // the calibration file it was read from (cam0/sensor.yaml), for messages
};

struct ImuCalibration {
  Pose T_BS;  // IMU -> body (identity when the body frame is the IMU frame)
  double rate_hz = 0.0;
  double gyro_noise_density = 0.0;   // rad/s/sqrt(Hz)
  double gyro_random_walk = 0.0;     // rad/s^2/sqrt(Hz)
  double accel_noise_density = 0.0;  // m/s^2/sqrt(Hz)
  double accel_random_walk = 0.0;    // m/s^3/sqrt(Hz)
};

// For rotor-speed datasets: thrust = thrust_coefficient / mass * sum(w_i^2) * thrust_axis.
struct RotorCalibration {
  double mass = 0.0;                 // kg
  double thrust_coefficient = 0.0;   // N s^2 rad^-2
  Vec3 thrust_axis = Vec3::UnitZ();  // IMU frame unit vector
};

// Where an image message lies inside a container file (a ROS bag): the chunk record starting
// at byte chunk_pos, and the message bytes [offset, offset + size) of its uncompressed data.
struct ContainerSpan {
  std::uint64_t chunk_pos = 0;
  std::uint64_t offset = 0;
  std::uint64_t size = 0;
  bool compressed_image = false;  // sensor_msgs/CompressedImage rather than sensor_msgs/Image
};

// An image listed by the camera file or the bag; pixels are loaded on demand by the io library.
struct ImageRef {
  Timestamp t = 0;
  std::string path;  // image file, or the container file when `span` is set
  std::optional<ContainerSpan> span;
  // The camera file and line that list the image (cam0/data.csv row), for error messages;
  // empty / 0 when the image did not come from such a file.
  std::string list_file;
  long list_line = 0;
};

// A ground-truth pixel observation of a known landmark (simulated sequences only).
struct LandmarkObservation {
  Timestamp t = 0;
  int landmark_id = 0;
  double u = 0.0, v = 0.0;  // distorted pixel coordinates
};

struct Sequence {
  std::string name;
  std::string source;  // where it was read from

  std::optional<ImuCalibration> imu_calibration;
  std::vector<ImuSample> imu;
  std::vector<ThrustSample> thrust;
  std::optional<RotorCalibration> rotor_calibration;
  std::vector<RotorSample> rotor;
  std::optional<CameraCalibration> camera;
  std::vector<ImageRef> images;
  std::vector<GroundTruthState> groundtruth;
  std::vector<ForceSample> forces;
  std::map<int, Vec3> landmarks;  // id -> world position (simulated sequences only)
  std::vector<LandmarkObservation> landmark_observations;

  std::vector<std::string> warnings;  // recoverable oddities met while reading, with counts

  bool hasImu() const { return !imu.empty(); }
  bool hasThrust() const { return !thrust.empty() || (!rotor.empty() && rotor_calibration); }
  bool hasImages() const { return camera.has_value() && !images.empty(); }
  bool hasGroundTruth() const { return !groundtruth.empty(); }
};

// The thrust channel of a sequence: thrust0 if present, else computed from rotor speeds as
// thrust_coefficient / mass * sum(w_i^2) along the thrust axis (FORMATS.md); empty if neither.
inline std::vector<ThrustSample> thrustSamples(const Sequence& seq) {
  if (!seq.thrust.empty() || seq.rotor.empty() || !seq.rotor_calibration) return seq.thrust;
  const RotorCalibration& c = *seq.rotor_calibration;
  std::vector<ThrustSample> out;
  out.reserve(seq.rotor.size());
  for (const RotorSample& r : seq.rotor)
    out.push_back({r.t, c.thrust_coefficient / c.mass * r.speeds.squaredNorm() * c.thrust_axis});
  return out;
}

// Ground-truth state at t (linear / slerp interpolation between the samples around t; biases
// when the ground truth has them). Throws InputError when t is outside the ground truth.
NavState groundTruthState(const Sequence& seq, Timestamp t);

// The flight up to and including time `end`: every time-stamped stream (IMU, thrust, rotor
// speeds, images, ground truth, forces, landmark observations) cut after `end`; calibrations,
// landmarks and warnings kept. For runs on the first seconds of a flight (run.duration_s).
Sequence sequenceUntil(const Sequence& seq, Timestamp end);

}  // namespace hdvio
