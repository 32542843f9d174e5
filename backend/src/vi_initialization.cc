#include "hdvio/backend/vi_initialization.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "hdvio/core/error.h"

namespace hdvio {
namespace {

std::string fmt(double x) {
  std::ostringstream s;
  s.precision(3);
  s << x;
  return s.str();
}

ViInitResult failure(ViInitResult r, ViInitFailure kind, const std::string& reason) {
  r.success = false;
  r.failure = kind;
  r.reason = reason;
  r.states.clear();
  r.landmarks_W.clear();
  return r;
}

double yawOf(const Mat3& R) { return std::atan2(R(1, 0), R(0, 0)); }

}  // namespace

ViInitResult initializeVisualInertial(const std::vector<FrameObservations>& frames,
                                      const std::vector<ImuSample>& imu, const CameraModel& camera,
                                      const Pose& T_BC, const ImuNoiseParams& imu_params,
                                      const ViInitOptions& options) {
  ViInitResult out;
  const int n = static_cast<int>(frames.size());
  if (n < std::max(2, options.min_frames))
    return failure(out, ViInitFailure::kNotEnoughData, "only " + std::to_string(n) + " frames");
  for (int k = 1; k < n; ++k)
    if (frames[k].t <= frames[k - 1].t)
      return failure(out, ViInitFailure::kNotEnoughData, "frame times do not increase");
  if (imu.empty() || imu.front().t > frames.front().t || imu.back().t < frames.back().t)
    return failure(out, ViInitFailure::kNotEnoughData, "IMU does not cover the frames");

  // Preintegration between consecutive frames, first with zero bias.
  std::vector<PreintegratedImu> preint;
  try {
    for (int k = 0; k + 1 < n; ++k)
      preint.push_back(
          PreintegratedImu::integrate(imu, frames[k].t, frames[k + 1].t, Vec6::Zero(), imu_params));
  } catch (const InputError& e) {
    return failure(out, ViInitFailure::kNotEnoughData,
                   std::string("IMU preintegration: ") + e.what());
  }

  // Bearings and the gyro rotations that seed the SfM.
  const Mat3 R_BC = T_BC.R();
  std::vector<vi_init::BearingFrame> bearings(n);
  for (int k = 0; k < n; ++k)
    for (const auto& f : frames[k].features) {
      const Vec3 b = camera.unproject(f.uv);
      if (b.allFinite() && b.z() > 0.1) bearings[k].bearings[f.landmark_id] = b;
    }
  std::vector<Mat3> R_C0C_prior(n, Mat3::Identity());
  Mat3 R_B0B = Mat3::Identity();
  for (int k = 1; k < n; ++k) {
    R_B0B = normalizeRotation(R_B0B * preint[k - 1].deltaR());
    R_C0C_prior[k] = R_BC.transpose() * R_B0B * R_BC;
  }
  const double focal = 0.5 * (camera.fu() + camera.fv());

  const vi_init::SfmResult sfm =
      vi_init::reconstructUpToScale(bearings, R_C0C_prior, focal, options.sfm);
  out.reference_frame = sfm.reference_frame;
  out.parallax_deg = sfm.reference_parallax_rad * 180.0 / M_PI;
  out.reprojection_rms_px = sfm.rms_reprojection_px;
  if (!sfm.success) {
    const bool parallax =
        sfm.reference_frame >= 0 && sfm.reference_parallax_rad < options.sfm.min_parallax_rad;
    return failure(out, parallax ? ViInitFailure::kInsufficientParallax : ViInitFailure::kVisual,
                   "visual SfM: " + sfm.reason);
  }
  if (sfm.rms_reprojection_px > options.max_reprojection_rms_px)
    return failure(out, ViInitFailure::kVisual,
                   "visual SfM: reprojection rms " + fmt(sfm.rms_reprojection_px) + " px");

  std::vector<vi_init::AlignmentFrame> af(n);
  for (int k = 0; k < n; ++k) {
    af[k].R_C0B = sfm.T_C0C[k].R() * R_BC.transpose();
    af[k].p_C0C = sfm.T_C0C[k].p;
  }

  // Gyro bias, re-integrating with each new estimate.
  Vec6 bias = Vec6::Zero();
  for (int it = 0; it < std::max(1, options.gyro_bias_iterations); ++it) {
    bias.head<3>() = vi_init::estimateGyroBias(af, preint);
    if (!bias.allFinite() || bias.head<3>().norm() > options.max_gyro_bias)
      return failure(
          out, ViInitFailure::kInconsistent,
          "gyro bias " + fmt(bias.head<3>().norm()) + " rad/s: visual and gyro rotations disagree");
    for (auto& p : preint) p = p.reintegrated(bias);
  }

  const Vec3 p_BC = T_BC.p;
  const vi_init::AlignmentResult lin = vi_init::alignLinear(af, preint, p_BC);
  out.gravity_norm_linear = lin.g_C0.norm();
  out.scale = lin.scale;
  out.scale_relative_std = lin.scale_relative_std;
  if (!(lin.scale > 0.0))
    return failure(out, ViInitFailure::kInsufficientExcitation,
                   "linear alignment: non-positive scale " + fmt(lin.scale));
  if (std::abs(out.gravity_norm_linear - kGravity) > options.max_gravity_norm_error)
    return failure(out, ViInitFailure::kInsufficientExcitation,
                   "linear alignment: |g| = " + fmt(out.gravity_norm_linear) +
                       " m/s^2 (insufficient excitation or bad visual scale)");

  const vi_init::AlignmentResult ref =
      vi_init::refineGravity(af, preint, p_BC, lin.g_C0, options.alignment);
  out.scale = ref.scale;
  out.scale_relative_std = ref.scale_relative_std;
  out.alignment_rms = ref.rms_residual;
  if (!(ref.scale > 0.0))
    return failure(out, ViInitFailure::kInsufficientExcitation,
                   "gravity refinement: non-positive scale " + fmt(ref.scale));
  if (ref.scale_relative_std > options.max_scale_relative_std)
    return failure(out, ViInitFailure::kInsufficientExcitation,
                   "scale uncertain (relative std " + fmt(ref.scale_relative_std) +
                       "): insufficient acceleration");
  if (ref.rms_residual > options.max_alignment_rms)
    return failure(out, ViInitFailure::kInconsistent,
                   "alignment residual rms " + fmt(ref.rms_residual) +
                       ": visual and inertial motion disagree");
  bias.tail<3>() = preint.front().bias().tail<3>() + ref.accel_bias_delta;

  // Output gauge: rotate C0 so gravity points along -z, then remove the first body's yaw.
  const Mat3 R_tilt =
      Quat::FromTwoVectors(ref.g_C0.normalized(), -Vec3::UnitZ()).toRotationMatrix();
  const double yaw0 = yawOf(R_tilt * af[0].R_C0B);
  const Mat3 R_WC0 = Eigen::AngleAxisd(-yaw0, Vec3::UnitZ()).toRotationMatrix() * R_tilt;
  const double s = ref.scale;
  const Vec3 p_C0B0 = s * af[0].p_C0C - af[0].R_C0B * p_BC;
  for (int k = 0; k < n; ++k) {
    NavState st;
    st.t = frames[k].t;
    const Vec3 p_C0B = s * af[k].p_C0C - af[k].R_C0B * p_BC;
    st.T_WB = Pose(Mat3(R_WC0 * af[k].R_C0B), Vec3(R_WC0 * (p_C0B - p_C0B0)));
    st.v_W = R_WC0 * ref.v_C0[k];
    st.bias = bias;
    out.states.push_back(st);
  }
  for (const auto& [id, x] : sfm.points_C0) out.landmarks_W[id] = R_WC0 * (s * x - p_C0B0);
  out.success = true;
  return out;
}

ViInitializer::ViInitializer(const CameraModel& camera, const Pose& T_BC,
                             const ImuNoiseParams& imu_params, const ViInitOptions& options,
                             double window_s, int max_frames, int retry_every)
    : camera_(camera),
      T_BC_(T_BC),
      imu_params_(imu_params),
      options_(options),
      window_s_(window_s),
      max_frames_(std::max(2, max_frames)),
      retry_every_(std::max(1, retry_every)) {}

bool ViInitializer::addFrame(const FrameObservations& frame, const std::vector<ImuSample>& imu) {
  if (result_.success) return false;  // already reported
  window_.push_back(frame);
  const Timestamp span = fromSeconds(window_s_);
  while (window_.size() > 2 && frame.t - window_[1].t >= span) window_.pop_front();
  // Tolerate a small rate jitter: attempt once the window spans 95 % of window_s.
  if (secondsBetween(window_.front().t, frame.t) < 0.95 * window_s_) return false;
  if (attempts_ > 0 && ++since_attempt_ < retry_every_) return false;
  since_attempt_ = 0;
  ++attempts_;
  const int size = static_cast<int>(window_.size());
  const int stride = std::max(1, (size + max_frames_ / 2) / max_frames_);
  std::vector<FrameObservations> frames;
  for (int i = size - 1; i >= 0; i -= stride) frames.push_back(window_[i]);
  std::reverse(frames.begin(), frames.end());
  result_ = initializeVisualInertial(frames, imu, camera_, T_BC_, imu_params_, options_);
  return result_.success;
}

}  // namespace hdvio
