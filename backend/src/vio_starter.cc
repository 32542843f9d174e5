#include "hdvio/backend/vio_starter.h"

#include "hdvio/core/error.h"

namespace hdvio {

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

VioStarter::VioStarter(const Sequence& seq, const VioRunOptions& run,
                       const ImuNoiseParams& imu_params)
    : seq_(seq), run_(run) {
  if (!seq.camera) throw InputError(seq.source, 0, "sequence has no camera calibration");
  if (seq.imu.empty()) throw InputError(seq.source, 0, "sequence has no IMU data");
  if (run.visual_inertial_init && !run.init_from_groundtruth)
    vi_init_.emplace(CameraModel::fromCalibration(*seq.camera), seq.camera->T_BS, imu_params,
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
  if (run_.init_from_groundtruth)
    return decide(groundTruthState(seq_, frame.t), StartKind::kGroundTruth);
  // A moving start needs the visual-inertial alignment; it sees every frame from the first.
  if (vi_init_ && vi_init_->addFrame(frame, seq_.imu))
    return decide(vi_init_->result().latest(), StartKind::kVisualInertial);
  // Everything else needs enough IMU to see gravity.
  if (frame.t - seq_.imu.front().t < fromSeconds(run_.static_init_window_s)) return std::nullopt;
  const auto static_state = [&] {
    return staticInitialization(seq_.imu, frame.t, run_.static_init_window_s);
  };
  if (!vi_init_) return decide(static_state(), StartKind::kStatic);
  // At rest (no parallax, still IMU) the static initialization is valid. A start at rest should
  // not wait for a whole window, so before the first attempt a still IMU decides alone (it cannot
  // tell rest from a perfectly steady cruise); after an attempt the camera must agree. A start
  // that defeats the alignment for too long gets the static guess with its loose priors.
  const bool no_parallax = vi_init_->attempts() == 0 ||
                           vi_init_->result().failure == ViInitFailure::kInsufficientParallax;
  if (no_parallax && imuIsStill(seq_.imu, frame.t, run_.static_init_window_s))
    return decide(static_state(), StartKind::kStaticAtRest);
  if (frame.t - *first_frame_t_ > fromSeconds(run_.vi_init_timeout_s))
    return decide(static_state(), StartKind::kStaticTimeout);
  return std::nullopt;
}

}  // namespace hdvio
