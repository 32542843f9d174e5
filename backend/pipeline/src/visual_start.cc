#include "hdvio/pipeline/visual_start.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "hdvio/core/error.h"

namespace hdvio {

namespace {
struct ImuMeans {
  Vec3 acc = Vec3::Zero();
  Vec3 gyro = Vec3::Zero();
  double gyro_std = 0.0;  // root of the summed per-axis variances
  int n = 0;
};
ImuMeans imuMeans(const std::vector<ImuSample>& imu, Timestamp t, double window_s) {
  ImuMeans m;
  Vec3 gyro_sq = Vec3::Zero();
  for (const auto& s : imu) {
    if (s.t > t) break;
    if (s.t < t - fromSeconds(window_s)) continue;
    m.acc += s.accel;
    m.gyro += s.gyro;
    gyro_sq += s.gyro.cwiseProduct(s.gyro);
    ++m.n;
  }
  if (m.n > 0) {
    m.acc /= m.n;
    m.gyro /= m.n;
    m.gyro_std = std::sqrt(std::max(0.0, (gyro_sq / m.n - m.gyro.cwiseProduct(m.gyro)).sum()));
  }
  return m;
}
// At rest: the specific force is gravity and the gyro is steady. Its mean may be a bias (real
// MEMS gyros: EuRoC's is 0.08 rad/s), so it is only bounded loosely; vibration of a vehicle
// on the ground or hovering stays well below the spread of a real rotation.
bool still(const ImuMeans& m) {
  return m.n > 0 && m.gyro.norm() < 0.2 && m.gyro_std < 0.1 &&
         std::abs(m.acc.norm() - kGravity) < 0.3;
}
}  // namespace

bool imuIsStill(const std::vector<ImuSample>& imu, Timestamp t, double window_s) {
  return still(imuMeans(imu, t, window_s));
}

NavState staticInitialization(const std::vector<ImuSample>& imu, Timestamp t, double window_s) {
  const ImuMeans m = imuMeans(imu, t, window_s);
  if (m.n == 0)
    throw InputError("", 0, "static initialization: no IMU samples before the first frame");
  // The accelerometer measures -g in the body frame: find R_WB with R_WB * acc = +z |acc|.
  const Quat q = Quat::FromTwoVectors(m.acc.normalized(), Vec3::UnitZ());
  // Remove the yaw this leaves, so the gauge is yaw = 0.
  const Vec3 x_axis = q * Vec3::UnitX();
  const double yaw = std::atan2(x_axis.y(), x_axis.x());
  NavState s;
  s.t = t;
  s.T_WB = Pose(Quat(Eigen::AngleAxisd(-yaw, Vec3::UnitZ())) * q, Vec3::Zero());
  // The gyro bias starts at zero (the backend's bias prior, init_gyro_bias_sigma, lets the
  // window estimate it): a "still" IMU may be turning slowly, and its mean gyro is then the
  // rotation, not a bias (bench random_v5_wind: 0.025 rad/s at the start of the ramp taken as
  // bias, vio 0.173 m ATE against 0.065 m from zero). On the EuRoC excerpt the 0.08 rad/s mean
  // as bias gave 0.106 m against 0.014 m from zero (docs/vi_initialization.md).
  return s;
}


std::string toString(StartKind kind) {
  switch (kind) {
    case StartKind::kNone: return "none";
    case StartKind::kGroundTruth: return "ground truth";
    case StartKind::kVisualInertial: return "visual-inertial";
    case StartKind::kStatic: return "static";
    case StartKind::kStaticAtRest: return "static (at rest)";
    case StartKind::kStaticTimeout: return "static (timeout)";
  }
  return "none";
}

VioStarter::VioStarter(const CameraCalibration& camera, const std::vector<ImuSample>& imu,
                       const VioRunOptions& run, const ImuNoiseParams& imu_params,
                       GroundTruthFn ground_truth)
    : imu_(imu), run_(run), ground_truth_(std::move(ground_truth)) {
  if (run.init_from_groundtruth && !ground_truth_)
    throw InputError("", 0, "run.init_from_groundtruth needs ground truth (the sequence has none)");
  if (run.visual_inertial_init && !run.init_from_groundtruth)
    vi_init_.emplace(CameraModel::fromCalibration(camera), camera.T_BS, imu_params,
                     ViInitOptions{}, run.vi_init_window_s);
}

std::string VioStarter::notStartedReason() const {
  std::string why = "no first state: ";
  if (!first_frame_t_) return why + "no frame";
  if (!vi_init_) return why + "the sequence ends within the static initialization window";
  if (vi_init_->attempts() == 0)
    return why + "the sequence is shorter than the visual-inertial window " +
           "(run.vi_init_window_s) and the IMU is not still";
  return why + "the visual-inertial initialization failed " +
         std::to_string(vi_init_->attempts()) + " times (last: " + vi_init_->result().reason +
         ") and the sequence ends before run.vi_init_timeout_s";
}

const ViInitResult* VioStarter::viInitResult() const {
  return vi_init_ && vi_init_->attempts() > 0 ? &vi_init_->result() : nullptr;
}

std::optional<NavState> VioStarter::addFrame(const FrameObservations& frame) {
  if (decided_) return std::nullopt;
  if (!first_frame_t_) first_frame_t_ = frame.t;
  const auto decide = [&](const NavState& s, StartKind kind) {
    decided_ = true;
    kind_ = kind;
    return std::optional<NavState>(s);
  };
  if (run_.init_from_groundtruth) return decide(ground_truth_(frame.t), StartKind::kGroundTruth);
  if (imu_.empty()) return std::nullopt;  // frames before the first IMU sample
  // A moving start needs the visual-inertial alignment; it sees every frame from the first.
  if (vi_init_ && vi_init_->addFrame(frame, imu_))
    return decide(vi_init_->result().latest(), StartKind::kVisualInertial);
  // Everything else needs enough IMU to see gravity.
  if (frame.t - imu_.front().t < fromSeconds(run_.static_init_window_s)) return std::nullopt;
  const auto static_state = [&] {
    return staticInitialization(imu_, frame.t, run_.static_init_window_s);
  };
  if (!vi_init_) return decide(static_state(), StartKind::kStatic);
  // At rest (no parallax, still IMU) the static initialization is valid. A start at rest should
  // not wait for a whole window, so before the first attempt a still IMU decides alone (it cannot
  // tell rest from a perfectly steady cruise); after an attempt the camera must agree. A start
  // that defeats the alignment for too long gets the static guess with its loose priors.
  const bool no_parallax = vi_init_->attempts() == 0 ||
                           vi_init_->result().failure == ViInitFailure::kInsufficientParallax;
  if (no_parallax && imuIsStill(imu_, frame.t, run_.static_init_window_s))
    return decide(static_state(), StartKind::kStaticAtRest);
  if (frame.t - *first_frame_t_ > fromSeconds(run_.vi_init_timeout_s))
    return decide(static_state(), StartKind::kStaticTimeout);
  return std::nullopt;
}

}  // namespace hdvio
