#include "hdvio/sim/simulator.h"

#include <cmath>
#include <filesystem>
#include <random>

#include <opencv2/imgcodecs.hpp>

#include "hdvio/core/error.h"
#include "hdvio/sim/gate_detections.h"

namespace hdvio::sim {
namespace fs = std::filesystem;

CameraCalibration cameraCalibrationOf(const CameraSimConfig& c) {
  CameraCalibration cal;
  cal.T_BS = c.T_BS;
  cal.width = c.width;
  cal.height = c.height;
  cal.rate_hz = c.rate_hz;
  cal.fu = c.fu;
  cal.fv = c.fv;
  cal.cu = c.cu;
  cal.cv = c.cv;
  cal.distortion = c.distortion;
  cal.distortion_coefficients = c.distortion_coefficients;
  return cal;
}

Simulator::Simulator(const SimConfig& config) : config_(config), model_(config) {
  if (config_.camera.enabled) {
    camera_ = std::make_unique<CameraModel>(CameraModel::fromCalibration(cameraCalibrationOf(config_.camera)));
    const std::vector<GateConfig> gates =
        config_.trajectory.type == TrajectoryType::kRace ? model_.trajectory().orientedGates() : std::vector<GateConfig>{};
    scene_ = std::make_unique<Scene>(config_.scene, gates, config_.seed);
    renderer_ = std::make_unique<Renderer>(*scene_, *camera_);
    // The camera sits off the body origin: it must stay inside the room too.
    for (double t : cameraTimes()) {
      const Vec3 c = cameraPose(t).p;
      if ((c.array() <= config_.scene.room_min.array()).any() || (c.array() >= config_.scene.room_max.array()).any())
        throw InputError("", 0, "camera leaves the room at t = " + std::to_string(t) + " s");
    }
  }
}

Simulator::~Simulator() = default;

std::vector<double> Simulator::cameraTimes() const {
  std::vector<double> times;
  if (!config_.camera.enabled) return times;
  for (long j = 0;; ++j) {
    const Timestamp dt = static_cast<Timestamp>(std::llround(j * 1e9 / config_.camera.rate_hz));
    const double time = toSeconds(dt);
    if (time > config_.duration + 1e-9) break;
    times.push_back(time);
  }
  return times;
}

Pose Simulator::cameraPose(double time) const {
  const TrueState s = model_.evaluate(time);
  return Pose(s.R, s.p) * config_.camera.T_BS;
}

SimulationResult Simulator::simulate() const {
  SimulationResult result;
  Sequence& seq = result.sequence;
  seq.name = config_.name;
  seq.source = "hdvio_sim";
  const ImuSimConfig& imu = config_.imu;
  const VehicleConfig& veh = config_.vehicle;

  ImuCalibration imu_cal;
  imu_cal.rate_hz = imu.rate_hz;
  imu_cal.gyro_noise_density = imu.gyro_noise_density;
  imu_cal.gyro_random_walk = imu.gyro_random_walk;
  imu_cal.accel_noise_density = imu.accel_noise_density;
  imu_cal.accel_random_walk = imu.accel_random_walk;
  seq.imu_calibration = imu_cal;
  RotorCalibration rotor_cal;
  rotor_cal.mass = veh.mass;
  rotor_cal.thrust_coefficient = veh.thrust_coefficient;
  rotor_cal.thrust_axis = Vec3::UnitZ();
  seq.rotor_calibration = rotor_cal;

  std::mt19937_64 imu_rng(config_.seed * 2654435761ULL + 1);
  std::mt19937_64 thrust_rng(config_.seed * 2654435761ULL + 2);
  std::normal_distribution<double> normal(0.0, 1.0);
  auto noiseVec = [&](std::mt19937_64& rng) { return Vec3(normal(rng), normal(rng), normal(rng)); };

  // Continuous white noise of density sigma becomes sigma / sqrt(dt) per sample; a bias random
  // walk of density sigma_b moves by sigma_b * sqrt(dt) per sample (EuRoC/Kalibr convention).
  const double dt = 1.0 / imu.rate_hz;
  Vec3 bg = imu.initial_gyro_bias, ba = imu.initial_accel_bias;
  const long n = static_cast<long>(std::floor(config_.duration * imu.rate_hz + 1e-9));
  for (long k = 0; k <= n; ++k) {
    const Timestamp ts = config_.start_time_ns + static_cast<Timestamp>(std::llround(k * 1e9 / imu.rate_hz));
    const double time = secondsBetween(config_.start_time_ns, ts);
    const TrueState s = model_.evaluate(time);
    result.states.push_back(s);

    ImuSample sample;
    sample.t = ts;
    sample.gyro = s.omega + bg;
    sample.accel = s.specific_force + ba;
    if (imu.noise) {
      sample.gyro += imu.gyro_noise_density / std::sqrt(dt) * noiseVec(imu_rng);
      sample.accel += imu.accel_noise_density / std::sqrt(dt) * noiseVec(imu_rng);
    }
    seq.imu.push_back(sample);

    GroundTruthState gt;
    gt.t = ts;
    gt.T_WB = Pose(s.R, s.p);
    gt.v_W = s.v;
    gt.gyro_bias = bg;
    gt.accel_bias = ba;
    gt.has_velocity = gt.has_biases = true;
    seq.groundtruth.push_back(gt);

    // Thrust channel: a commanded thrust leads the true one through the first-order lag
    // T + lag dT/dt = command; miscalibration maps true to written as scale * x + bias.
    double channel = s.thrust;
    if (veh.thrust_output == VehicleConfig::ThrustOutput::kCommanded) channel += veh.thrust_lag * s.thrust_rate;
    channel = veh.thrust_scale * channel + veh.thrust_bias;
    if (veh.thrust_noise > 0.0) channel += veh.thrust_noise * normal(thrust_rng);
    seq.thrust.push_back(ThrustSample{ts, Vec3(0.0, 0.0, channel)});
    bool clamped = false;
    seq.rotor.push_back(RotorSample{ts, model_.rotorSpeeds(s, std::max(0.0, channel), &clamped)});
    if (clamped) ++result.clamped_rotor_samples;

    seq.forces.push_back(ForceSample{ts, s.external, s.drag});

    if (imu.noise) {
      bg += imu.gyro_random_walk * std::sqrt(dt) * noiseVec(imu_rng);
      ba += imu.accel_random_walk * std::sqrt(dt) * noiseVec(imu_rng);
    }
  }
  if (result.clamped_rotor_samples > 0)
    seq.warnings.push_back(std::to_string(result.clamped_rotor_samples) +
                           " rotor samples needed negative rotor thrust (clamped to 0)");

  if (camera_) {
    seq.camera = cameraCalibrationOf(config_.camera);
    const std::vector<Vec3> points = scene_->sampleSurfacePoints(config_.scene.num_landmarks, config_.seed);
    for (size_t i = 0; i < points.size(); ++i) seq.landmarks[static_cast<int>(i)] = points[i];
    for (double time : cameraTimes()) {
      const Pose T_WC = cameraPose(time);
      const Pose T_CW = T_WC.inverse();
      for (size_t i = 0; i < points.size(); ++i) {
        const Vec3 p_C = T_CW * points[i];
        Eigen::Vector2d uv;
        if (!camera_->project(p_C, &uv) || !camera_->inImage(uv)) continue;
        // Strong distortion folds far-off-axis points into the image: keep only points whose
        // pixel maps back to the same ray.
        if (!mapsBackToRay(*camera_, uv, p_C)) continue;
        if (scene_->segmentBlocked(T_WC.p, points[i])) continue;
        seq.landmark_observations.push_back(
            LandmarkObservation{timestampOf(time), static_cast<int>(i), uv.x(), uv.y()});
      }
    }
    if (config_.gate_detection.enabled && !scene_->gates().empty()) {
      std::vector<std::pair<Timestamp, Pose>> frames;
      for (double time : cameraTimes()) frames.emplace_back(timestampOf(time), cameraPose(time));
      result.gates = detectGateCorners(*scene_, *camera_, config_.gate_detection, frames, config_.seed);
    }
  }
  return result;
}

cv::Mat Simulator::renderFrame(double time, int frame_index) const {
  const CameraSimConfig& c = config_.camera;
  cv::Mat sum, frame;
  const int samples = c.motion_blur_samples;
  for (int i = 0; i < samples; ++i) {
    const double t = samples > 1 ? time + c.exposure_time * (static_cast<double>(i) / (samples - 1) - 0.5) : time;
    renderer_->render(cameraPose(t), &frame);
    if (i == 0) {
      sum = frame.clone();
    } else {
      sum += frame;
    }
  }
  if (samples > 1) sum *= 1.0 / samples;
  if (c.exposure_variation > 0.0) {
    const double phase = static_cast<double>(config_.seed % 1000) * 0.001 * 2.0 * M_PI;
    sum *= 1.0 + c.exposure_variation * std::sin(2.0 * M_PI * time / c.exposure_period + phase);
  }
  if (c.noise_std > 0.0) {
    cv::Mat noise(sum.size(), CV_32F);
    cv::RNG rng(config_.seed * 1000003ULL + static_cast<std::uint64_t>(frame_index) + 1);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, c.noise_std);
    sum += noise;
  }
  cv::Mat out;
  sum.convertTo(out, CV_8U);  // rounds and saturates
  return out;
}

void Simulator::renderImages(SimulationResult* result, const std::string& image_dir) const {
  if (!camera_) return;
  fs::create_directories(image_dir);
  const std::vector<int> png{cv::IMWRITE_PNG_COMPRESSION, config_.camera.png_compression};
  const std::vector<double> times = cameraTimes();
  for (size_t j = 0; j < times.size(); ++j) {
    const Timestamp ts = timestampOf(times[j]);
    const std::string path = (fs::path(image_dir) / (std::to_string(ts) + ".png")).string();
    if (!cv::imwrite(path, renderFrame(times[j], static_cast<int>(j)), png))
      throw InputError(path, 0, "cannot write image");
    ImageRef ref;
    ref.t = ts;
    ref.path = path;
    result->sequence.images.push_back(ref);
  }
}

}  // namespace hdvio::sim
