#include "hdvio/backend/vio_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <random>

#include "hdvio/backend/vio_starter.h"
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
  // The mean gyro is a bias estimate only if the vehicle really was still, and only a near-zero
  // mean is taken (as before still() tolerated a bias): on the EuRoC excerpt, starting from its
  // 0.08 rad/s mean gave 0.106 m ATE against 0.014 m from zero (docs/vi_initialization.md).
  if (still(m) && m.gyro.norm() < 0.05) s.bias.head<3>() = m.gyro;
  return s;
}

NavState groundTruthState(const Sequence& seq, Timestamp t) {
  const auto& gt = seq.groundtruth;
  if (gt.empty() || t < gt.front().t || t > gt.back().t)
    throw InputError(seq.source, 0, "no ground truth at the first frame time");
  auto hi = std::lower_bound(gt.begin(), gt.end(), t,
                             [](const GroundTruthState& s, Timestamp tt) { return s.t < tt; });
  auto lo = hi == gt.begin() ? hi : std::prev(hi);
  const double a = hi->t == lo->t ? 0.0 : secondsBetween(lo->t, t) / secondsBetween(lo->t, hi->t);
  NavState s;
  s.t = t;
  s.T_WB = Pose(lo->T_WB.q.slerp(a, hi->T_WB.q), (1 - a) * lo->T_WB.p + a * hi->T_WB.p);
  s.v_W = (1 - a) * lo->v_W + a * hi->v_W;
  if (lo->has_biases) s.bias << lo->gyro_bias, lo->accel_bias;
  return s;
}

std::vector<FrameObservations> framesFromTracks(const Sequence& seq, double sigma,
                                                std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<FrameObservations> frames;
  for (const auto& o : seq.landmark_observations) {
    if (frames.empty() || frames.back().t != o.t) frames.push_back({o.t, {}});
    Vec2 uv(o.u, o.v);
    if (sigma > 0.0) uv += sigma * Vec2(noise(rng), noise(rng));
    frames.back().features.push_back({o.landmark_id, uv});
  }
  // Frames without any observation still carry a time (tracking loss): keep image times.
  for (const auto& img : seq.images) {
    auto it = std::lower_bound(frames.begin(), frames.end(), img.t,
                               [](const FrameObservations& f, Timestamp t) { return f.t < t; });
    if (it == frames.end() || it->t != img.t) frames.insert(it, FrameObservations{img.t, {}});
  }
  return frames;
}

VioRunOutput runVioOnTracks(const Sequence& seq, const VioBackendOptions& options,
                            const VioRunOptions& run,
                            ResidualForceSource residual_force) {
  if (!seq.camera) throw InputError(seq.source, 0, "sequence has no camera calibration");
  if (seq.imu.empty()) throw InputError(seq.source, 0, "sequence has no IMU data");
  const std::vector<ThrustSample> thrust = thrustSamples(seq);
  if (usesDynamics(options.method) && thrust.empty())
    throw InputError(seq.source, 0, "method '" + toString(options.method) +
                                        "' needs thrust (thrust0 or rotor0 with calibration)");
  const auto frames = framesFromTracks(seq, run.pixel_noise_sigma, run.seed);
  if (frames.empty()) throw InputError(seq.source, 0, "sequence has no landmark tracks or frames");

  VioBackendOptions opts = options;
  if (!run.init_from_groundtruth) {
    // Without ground truth the first velocity and tilt are guesses: let vision and IMU fix them.
    opts.init_velocity_sigma = std::max(opts.init_velocity_sigma, run.guess_velocity_sigma);
    opts.init_tilt_sigma = std::max(opts.init_tilt_sigma, run.guess_tilt_sigma);
  }
  VioBackend backend(opts, CameraModel::fromCalibration(*seq.camera), seq.camera->T_BS,
                     std::move(residual_force));
  VioRunOutput out;
  std::size_t imu_next = 0, thrust_next = 0;
  const auto feed_until = [&](Timestamp t) {
    while (imu_next < seq.imu.size() && seq.imu[imu_next].t <= t) backend.addImu(seq.imu[imu_next++]);
    while (thrust_next < thrust.size() && thrust[thrust_next].t <= t)
      backend.addThrust(thrust[thrust_next++]);
  };
  VioStarter starter(seq, run, opts.imu);
  const auto start = std::chrono::steady_clock::now();
  for (const auto& frame : frames) {
    feed_until(frame.t);
    if (!backend.initialized()) {
      const std::optional<NavState> initial = starter.addFrame(frame);
      if (!initial) continue;
      backend.initialize(*initial);
      out.start = starter.kind();
      out.start_t = frame.t;
      out.visual_inertial_start = out.start == StartKind::kVisualInertial;
      FrameResult first;
      first.processed = true;
      first.keyframe = true;
      first.state = backend.latestState();
      out.frames.push_back(first);
      out.states.push_back(first.state);
      continue;
    }
    const FrameResult r = backend.addFrame(frame);
    if (!r.processed) continue;
    out.frames.push_back(r);
    out.states.push_back(r.state);
  }
  out.backend_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.vi_init_attempts = starter.viInitAttempts();
  if (const ViInitResult* r = starter.viInitResult()) out.vi_init = *r;
  if (!starter.started()) throw InputError(seq.source, 0, starter.notStartedReason());
  return out;
}

}  // namespace hdvio
