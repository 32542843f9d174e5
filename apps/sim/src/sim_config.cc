#include "hdvio/sim/sim_config.h"

#include <cmath>

#include "hdvio/core/error.h"

namespace hdvio::sim {
std::string toString(TrajectoryType type) {
  switch (type) {
    case TrajectoryType::kHover: return "hover";
    case TrajectoryType::kCircle: return "circle";
    case TrajectoryType::kLemniscate: return "lemniscate";
    case TrajectoryType::kRandom: return "random";
    case TrajectoryType::kRace: return "race";
  }
  return "circle";
}

namespace {

[[noreturn]] void fail(const ConfigReader& r, const std::string& key, const std::string& problem) {
  const std::string path = r.path().empty() ? key : r.path() + "." + key;
  throw InputError(r.file(), 0, path + ": " + problem);
}

void readVec3(const ConfigReader& r, const std::string& key, Vec3* v, bool required = false) {
  std::vector<double> x{(*v)[0], (*v)[1], (*v)[2]};
  if (required) {
    r.read(key, &x);
  } else {
    r.readOptional(key, &x);
  }
  if (x.size() != 3) fail(r, key, "expected 3 numbers, got " + std::to_string(x.size()));
  *v = Vec3(x[0], x[1], x[2]);
}

void readPositive(const ConfigReader& r, const std::string& key, double* v, double hi = 1e12) {
  r.readInRange(key, v, 0.0, hi);
  if (!(*v > 0.0)) fail(r, key, "must be > 0");
}

TrajectoryConfig readTrajectory(const ConfigReader& r) {
  TrajectoryConfig c;
  r.readEnum("type", &c.type,
             {{"hover", TrajectoryType::kHover}, {"circle", TrajectoryType::kCircle},
              {"lemniscate", TrajectoryType::kLemniscate}, {"random", TrajectoryType::kRandom},
              {"race", TrajectoryType::kRace}},
             true);
  readVec3(r, "center", &c.center);
  r.readInRange("max_speed", &c.max_speed, 0.0, 40.0);
  r.readInRange("ramp_time", &c.ramp_time, 0.0, 1000.0);
  if (c.type == TrajectoryType::kCircle) {
    readPositive(r, "radius", &c.radius, 1000.0);
  }
  if (c.type == TrajectoryType::kCircle || c.type == TrajectoryType::kLemniscate) {
    r.readInRange("height_amplitude", &c.height_amplitude, 0.0, 100.0);
  }
  if (c.type == TrajectoryType::kLemniscate || c.type == TrajectoryType::kRandom) {
    readVec3(r, "extent", &c.extent);
    for (int i = 0; i < 3; ++i)
      if (c.extent[i] < 0.0) fail(r, "extent", "half sizes must be >= 0");
  }
  if (c.type == TrajectoryType::kRandom) r.readInRange("random_features", &c.random_features, 4, 512);
  if (c.type == TrajectoryType::kRace) {
    for (const ConfigReader& g : r.list("gates")) {
      GateConfig gate;
      readVec3(g, "position", &gate.position, true);
      g.finish();
      c.gates.push_back(gate);
    }
    if (c.gates.size() < 3) fail(r, "gates", "a race track needs at least 3 gates");
  }
  if (c.type != TrajectoryType::kHover && !(c.max_speed > 0.0)) fail(r, "max_speed", "must be > 0 for a moving trajectory");
  r.finish();
  return c;
}

YawConfig readYaw(const ConfigReader& r) {
  YawConfig c;
  r.readEnum("mode", &c.mode,
             {{"fixed", YawMode::kFixed}, {"rate", YawMode::kRate},
              {"oscillate", YawMode::kOscillate}, {"forward", YawMode::kForward}},
             true);
  double deg = 0.0;
  r.readInRange("value_deg", &deg, -360.0, 360.0);
  c.value = deg * M_PI / 180.0;
  if (c.mode == YawMode::kRate) {
    double rate_deg = 0.0;
    r.readInRange("rate_deg", &rate_deg, -2000.0, 2000.0, true);
    c.rate = rate_deg * M_PI / 180.0;
  }
  if (c.mode == YawMode::kOscillate) {
    double amp_deg = 0.0;
    r.readInRange("amplitude_deg", &amp_deg, 0.0, 180.0, true);
    c.amplitude = amp_deg * M_PI / 180.0;
    r.readInRange("frequency", &c.frequency, 0.0, 10.0);
  }
  r.finish();
  return c;
}

VehicleConfig readVehicle(const ConfigReader& r) {
  VehicleConfig c;
  readPositive(r, "mass", &c.mass, 1000.0);
  readPositive(r, "thrust_coefficient", &c.thrust_coefficient, 1.0);
  r.readInRange("torque_coefficient", &c.torque_coefficient, 0.0, 1.0);
  readPositive(r, "arm_length", &c.arm_length, 10.0);
  readVec3(r, "inertia", &c.inertia);
  readVec3(r, "rotor_drag", &c.rotor_drag);
  for (int i = 0; i < 3; ++i) {
    if (c.inertia[i] <= 0.0) fail(r, "inertia", "must be > 0");
    if (c.rotor_drag[i] < 0.0) fail(r, "rotor_drag", "must be >= 0");
  }
  r.readInRange("fuselage_drag", &c.fuselage_drag, 0.0, 10.0);
  r.readEnum("thrust_output", &c.thrust_output,
             {{"measured", VehicleConfig::ThrustOutput::kMeasured},
              {"commanded", VehicleConfig::ThrustOutput::kCommanded}});
  r.readInRange("thrust_scale", &c.thrust_scale, 0.1, 10.0);
  r.readInRange("thrust_bias", &c.thrust_bias, -20.0, 20.0);
  r.readInRange("thrust_lag", &c.thrust_lag, 0.0, 1.0);
  r.readInRange("thrust_noise", &c.thrust_noise, 0.0, 20.0);
  r.finish();
  return c;
}

WindConfig readWind(const ConfigReader& r) {
  WindConfig c;
  readVec3(r, "steady", &c.steady);
  if (c.steady.norm() > 30.0) fail(r, "steady", "wind above 30 m/s is not supported");
  if (r.has("jets")) {
    for (const ConfigReader& j : r.list("jets")) {
      JetConfig jet;
      readVec3(j, "origin", &jet.origin, true);
      readVec3(j, "direction", &jet.direction, true);
      if (jet.direction.norm() < 1e-6) fail(j, "direction", "must be non-zero");
      jet.direction.normalize();
      j.readInRange("speed", &jet.speed, 0.0, 30.0, true);
      readPositive(j, "radius", &jet.radius, 100.0);
      readPositive(j, "length", &jet.length, 1000.0);
      j.finish();
      c.jets.push_back(jet);
    }
  }
  r.readInRange("gust_std", &c.gust_std, 0.0, 10.0);
  readPositive(r, "gust_time_scale", &c.gust_time_scale, 1000.0);
  r.finish();
  return c;
}

ForceEventConfig readForce(const ConfigReader& r) {
  ForceEventConfig c;
  r.readEnum("type", &c.type,
             {{"pull", ForceEventConfig::Type::kPull},
              {"payload", ForceEventConfig::Type::kPayload}},
             true);
  r.readInRange("start", &c.start, 0.0, 1e6, true);
  r.readInRange("end", &c.end, 0.0, 1e9);
  readPositive(r, "ramp", &c.ramp, 100.0);
  if (c.end <= c.start) fail(r, "end", "must be after start");
  if (c.type == ForceEventConfig::Type::kPull) {
    readVec3(r, "force", &c.force, true);
    if (c.force.norm() > 30.0) fail(r, "force", "above 30 m/s^2 is not supported");
  } else {
    readPositive(r, "mass", &c.mass, 100.0);
  }
  r.finish();
  return c;
}

ImuSimConfig readImu(const ConfigReader& r) {
  ImuSimConfig c;
  r.readInRange("rate_hz", &c.rate_hz, 200.0, 10000.0);
  r.readInRange("gyro_noise_density", &c.gyro_noise_density, 0.0, 1.0);
  r.readInRange("gyro_random_walk", &c.gyro_random_walk, 0.0, 1.0);
  r.readInRange("accel_noise_density", &c.accel_noise_density, 0.0, 10.0);
  r.readInRange("accel_random_walk", &c.accel_random_walk, 0.0, 10.0);
  r.readOptional("noise", &c.noise);
  readVec3(r, "initial_gyro_bias", &c.initial_gyro_bias);
  readVec3(r, "initial_accel_bias", &c.initial_accel_bias);
  r.finish();
  return c;
}

CameraSimConfig readCamera(const ConfigReader& r) {
  CameraSimConfig c;
  r.readOptional("enabled", &c.enabled);
  std::vector<int> resolution{c.width, c.height};
  r.readOptional("resolution", &resolution);
  if (resolution.size() != 2 || resolution[0] < 16 || resolution[1] < 16 || resolution[0] > 8192 ||
      resolution[1] > 8192)
    fail(r, "resolution", "expected [width, height] between 16 and 8192");
  c.width = resolution[0];
  c.height = resolution[1];
  readPositive(r, "rate_hz", &c.rate_hz, 1000.0);
  std::vector<double> intr{c.fu, c.fv, c.cu, c.cv};
  r.readOptional("intrinsics", &intr);
  if (intr.size() != 4 || intr[0] <= 0.0 || intr[1] <= 0.0)
    fail(r, "intrinsics", "expected [fu, fv, cu, cv] with fu, fv > 0");
  c.fu = intr[0]; c.fv = intr[1]; c.cu = intr[2]; c.cv = intr[3];
  r.readEnum("distortion_model", &c.distortion,
             {{"none", DistortionModel::kNone},
              {"radial-tangential", DistortionModel::kRadialTangential}});
  if (c.distortion == DistortionModel::kRadialTangential) {
    r.read("distortion_coefficients", &c.distortion_coefficients);
    if (c.distortion_coefficients.size() != 4)
      fail(r, "distortion_coefficients", "radial-tangential needs [k1, k2, p1, p2]");
  }
  if (r.has("T_BS")) {
    std::vector<double> m;
    r.read("T_BS", &m);
    if (m.size() != 16) fail(r, "T_BS", "expected 16 numbers (row-major 4x4)");
    Mat4 T = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(m.data());
    const Mat3 R = T.topLeftCorner<3, 3>();
    if ((R.transpose() * R - Mat3::Identity()).norm() > 1e-3 || R.determinant() < 0.0)
      fail(r, "T_BS", "top-left 3x3 block is not a rotation");
    c.T_BS = Pose(normalizeRotation(R), Vec3(T.topRightCorner<3, 1>()));
  }
  r.readInRange("noise_std", &c.noise_std, 0.0, 100.0);
  r.readInRange("exposure_variation", &c.exposure_variation, 0.0, 1.0);
  readPositive(r, "exposure_period", &c.exposure_period, 1e6);
  r.readInRange("motion_blur_samples", &c.motion_blur_samples, 1, 32);
  readPositive(r, "exposure_time", &c.exposure_time, 1.0);
  r.readInRange("png_compression", &c.png_compression, 0, 9);
  if (c.exposure_time >= 1.0 / c.rate_hz) fail(r, "exposure_time", "must be shorter than the frame period");
  r.finish();
  return c;
}

SceneConfig readScene(const ConfigReader& r) {
  SceneConfig c;
  readVec3(r, "room_min", &c.room_min);
  readVec3(r, "room_max", &c.room_max);
  for (int i = 0; i < 3; ++i)
    if (c.room_max[i] - c.room_min[i] < 1.0) fail(r, "room_max", "room must be at least 1 m in each axis");
  r.readInRange("texel_size", &c.texel_size, 0.002, 0.5);
  const Vec3 size = c.room_max - c.room_min;
  const double texels = std::max({size.x() * size.y(), size.y() * size.z(), size.x() * size.z()}) /
                        (c.texel_size * c.texel_size);
  if (texels > 64e6) fail(r, "texel_size", "too fine for this room (a face would exceed 64 Mtexels)");
  r.readOptional("render_gates", &c.render_gates);
  readPositive(r, "gate_inner_size", &c.gate_inner_size, 20.0);
  readPositive(r, "gate_border", &c.gate_border, 5.0);
  r.readInRange("num_landmarks", &c.num_landmarks, 0, 1000000);
  r.readInRange("min_clearance", &c.min_clearance, 0.0, 10.0);
  r.finish();
  return c;
}

GateDetectionConfig readGateDetection(const ConfigReader& r) {
  GateDetectionConfig c;
  r.readOptional("enabled", &c.enabled);
  r.readInRange("pixel_noise", &c.pixel_noise, 0.0, 100.0);
  r.readInRange("max_distance", &c.max_distance, 0.1, 1000.0);
  r.readInRange("dropout", &c.dropout, 0.0, 1.0);
  r.finish();
  return c;
}

}  // namespace

Pose CameraSimConfig::defaultCameraMount() {
  Mat3 R;  // columns: camera x, y, z axes in body coordinates
  R.col(0) = Vec3(0.0, -1.0, 0.0);
  R.col(1) = Vec3(0.0, 0.0, -1.0);
  R.col(2) = Vec3(1.0, 0.0, 0.0);
  return Pose(R, Vec3(0.05, 0.0, 0.0));
}

SimConfig loadSimConfig(const ConfigReader& r) {
  SimConfig c;
  r.readOptional("name", &c.name);
  int seed = static_cast<int>(c.seed);
  r.readInRange("seed", &seed, 0, 2000000000);
  c.seed = static_cast<std::uint64_t>(seed);
  r.readInRange("duration", &c.duration, 0.1, 3600.0, true);
  r.readOptional("start_time_ns", &c.start_time_ns);
  if (c.start_time_ns < 0) fail(r, "start_time_ns", "must be >= 0");
  c.trajectory = readTrajectory(r.section("trajectory"));
  if (r.has("yaw")) c.yaw = readYaw(r.section("yaw"));
  if (r.has("vehicle")) c.vehicle = readVehicle(r.section("vehicle"));
  if (r.has("wind")) c.wind = readWind(r.section("wind"));
  if (r.has("forces")) {
    for (const ConfigReader& f : r.list("forces")) c.forces.push_back(readForce(f));
  }
  if (r.has("imu")) c.imu = readImu(r.section("imu"));
  if (r.has("camera")) c.camera = readCamera(r.section("camera"));
  if (r.has("scene")) c.scene = readScene(r.section("scene"));
  if (r.has("gate_detection")) c.gate_detection = readGateDetection(r.section("gate_detection"));
  if (c.yaw.mode == YawMode::kForward && c.trajectory.type == TrajectoryType::kHover)
    fail(r, "yaw.mode", "'forward' needs a moving trajectory");
  r.finish();
  return c;
}

}  // namespace hdvio::sim
