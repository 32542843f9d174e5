#pragma once
// The updaters of the IMO EKF driver (imo_stepper.h), each chosen once by the estimator:
//   DisplacementUpdater      clones on a fixed grid at the update rate; once the clones span
//                            one window, the source's displacement between the window's first
//                            and last clone updates the filter and every clone up to the
//                            window's start is marginalized (imo, tlio, model_ekf; gate_io
//                            with a network). docs/imo.md.
//   DisplacementConcatenation net_only: no filter update; positions on the grid
//                            p(t) = p(t - window) + displacement(t), the first window's from the
//                            filter's dead reckoning. Velocity reported = displacement / window.
//   GateCornerUpdater        the reprojections of known race-gate corners at every camera
//                            frame (gate_io). docs/gate_io.md.
#include <deque>
#include <vector>

#include "hdvio/backend/imo/displacement_source.h"
#include "hdvio/backend/imo/gate_reprojection.h"
#include "hdvio/backend/imo/imo_run_support.h"
#include "hdvio/backend/imo/imo_stepper.h"

namespace hdvio::imo {

class DisplacementUpdater : public ImoUpdater {
 public:
  // Throws as checkRunOptions, or std::invalid_argument without a source.
  DisplacementUpdater(const ImoRunOptions& options, DisplacementSource source);

  void start(ImoFilter& filter, ImoRunOutput& out) override;
  void propagated(const ImoFilter& filter, const Vec3& gyro, Timestamp t_from, Timestamp t_to) override;
  Timestamp nextTime() const override { return next_grid_; }
  void update(ImoFilter& filter, ImoRunOutput& out) override;
  Timestamp nextWindowEnd() const override { return next_grid_; }

 private:
  const ImoRunOptions options_;
  const DisplacementSource source_;
  const Timestamp period_, window_;
  const std::size_t window_clones_;
  const Mat3 fixed_cov_;
  Timestamp next_grid_ = kNoUpdate;
  // The gyro integration since the start (filter bias at each step): carries a clone's
  // rotation across a window.
  Quat gamma_ = Quat::Identity();
  Vec3 init_bg_ = Vec3::Zero(), init_ba_ = Vec3::Zero();
  RotationHistory history_;
};

class DisplacementConcatenation : public ImoUpdater {
 public:
  // Throws as checkRunOptions. The source must give pure displacements (no velocity or
  // attitude terms): std::invalid_argument at the update otherwise.
  DisplacementConcatenation(const ImoRunOptions& options, DisplacementSource source);

  void start(ImoFilter& filter, ImoRunOutput& out) override;
  void propagated(const ImoFilter& filter, const Vec3& gyro, Timestamp t_from, Timestamp t_to) override;
  Timestamp nextTime() const override { return next_grid_; }
  void update(ImoFilter& filter, ImoRunOutput& out) override;
  Timestamp nextWindowEnd() const override { return next_grid_; }

 private:
  const ImoRunOptions options_;
  const DisplacementSource source_;
  const Timestamp period_, window_;
  Timestamp init_t_ = 0;
  Timestamp next_grid_ = kNoUpdate;
  RotationHistory history_;  // the dead-reckoned attitude
  std::deque<std::pair<Timestamp, Vec3>> grid_positions_;
  Vec3 last_velocity_ = Vec3::Zero();
};

// The corners detected in one camera frame.
struct GateFrame {
  Timestamp t = 0;
  std::vector<GateCornerObservation> corners;
};

struct GateCornerOptions {
  double pixel_sigma = 1.5;         // px, corner detection noise
  double gate_probability = 0.999;  // chi-square gate per frame (2 k dof); <= 0 disables
  // Chi-square gate per corner (2 dof, each corner against its own 2x2 innovation covariance)
  // before the frame update: drops single bad corners and keeps the rest. <= 0 disables.
  double corner_gate_probability = -1.0;
};

class GateCornerUpdater : public ImoUpdater {
 public:
  // camera: the cam0 model; T_BC: camera -> body. Throws std::invalid_argument for a
  // non-positive pixel sigma.
  GateCornerUpdater(const GateCornerOptions& options, const CameraModel& camera, const Pose& T_BC);

  // A frame to apply in the IMU interval that holds its time: give it before the sample that
  // ends that interval. Ignored if not after the last sample stepped or before the previous
  // frame.
  void addFrame(const GateFrame& frame);

  void start(ImoFilter& filter, ImoRunOutput& out) override;
  void propagated(const ImoFilter&, const Vec3&, Timestamp, Timestamp t_to) override { stepped_ = t_to; }
  Timestamp nextTime() const override { return frames_.empty() ? kNoUpdate : frames_.front().t; }
  void update(ImoFilter& filter, ImoRunOutput& out) override;

 private:
  const GateCornerOptions options_;
  const CameraModel camera_;
  const Pose T_BC_;
  const double corner_threshold_, pixel_var_;
  Timestamp stepped_ = 0;
  std::deque<GateFrame> frames_;  // given, not yet applied
  double chi2_sum_ = 0.0;
};

}  // namespace hdvio::imo
