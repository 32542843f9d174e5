#pragma once
// The visual-inertial(-dynamics) backend: turns frames of landmark observations plus IMU and
// thrust buffers into states, factors and initial values for the sliding-window smoother, in
// one of four modes (vio, vimo, vid, hdvio) that differ only by the dynamics model made at
// construction (dynamics_model.h). The window holds the K most recent states and up to L older
// keyframes; leaving states are Schur-complemented into a prior.
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "hdvio/backend/dynamics_model.h"
#include "hdvio/core/frame_observations.h"
#include "hdvio/core/nav_state.h"
#include "hdvio/backend/sliding_window_smoother.h"
#include "hdvio/backend/vio_options.h"
#include "hdvio/core/camera_model.h"
#include "hdvio/factors/measurement_steps.h"

namespace hdvio {

struct FrameResult {
  bool processed = false;     // false: not enough IMU data yet for this frame
  bool keyframe = false;
  int observations_used = 0;  // reprojection factors added for this frame
  int landmarks_in_window = 0;
  int outliers_removed = 0;
  int solver_iterations = 0;
  bool solve_converged = true;  // false: the last solve stopped at max_iterations
  // false: a solve of this frame failed (a residual could not be evaluated at the start) and
  // left the window as it was
  bool solves_usable = true;
  double solve_time_s = 0.0;
  double cpu_time_s = 0.0;           // this thread's CPU time in addFrame (whole update)
  double marginalization_cpu_s = 0.0;  // part of cpu_time_s spent in window maintenance
  NavState state;
};

class VioBackend {
 public:
  // residual_force: the learned residual force provider (hdvio mode); null means zero.
  VioBackend(const VioBackendOptions& options, const CameraModel& camera, const Pose& T_BC,
             ResidualForceSource residual_force = nullptr);

  void addImu(const ImuSample& sample);
  void addThrust(const ThrustSample& sample);

  // Prior sigmas of the first state's velocity (m/s) and tilt (rad): what it is known to.
  struct StartUncertainty {
    double velocity_sigma = 0.0;
    double tilt_sigma = 0.0;
  };
  // Starts the window at state.t (a frame time) with priors around state; without an
  // uncertainty, the options' init_velocity_sigma and init_tilt_sigma.
  void initialize(const NavState& state);
  void initialize(const NavState& state, const StartUncertainty& uncertainty);
  bool initialized() const { return !states_.empty(); }

  // Requires IMU (and thrust for dynamics modes) up to frame.t.
  FrameResult addFrame(const FrameObservations& frame);

  NavState latestState() const;
  struct WindowPose {
    Timestamp t;
    Pose T_WB;
  };
  // Every pose in the window, oldest first.
  std::vector<WindowPose> windowPoses() const;
  // The smoother's estimate of a landmark (world frame); nullopt when it is not in the window.
  std::optional<Vec3> landmarkPosition(int landmark_id) const;
  const SlidingWindowSmoother& smoother() const { return smoother_; }

 private:
  struct StateSlot {
    std::uint64_t index;
    Timestamp t;
    bool keyframe;
  };
  struct Track {
    std::map<std::uint64_t, FeatureObservation> obs;  // state index -> observation
    // One reprojection factor per observation in the graph.
    std::map<std::uint64_t, SlidingWindowSmoother::FactorId> factors;
    bool in_graph = false;
  };

  NavState stateAt(std::uint64_t index, Timestamp t) const;
  InertialBuffers buffers() const { return {imu_, thrust_}; }
  void addInertialFactors(const StateSlot& from, std::uint64_t to, Timestamp t_to,
                          FactorGraph* graph, Values* values);
  bool isKeyframe(std::uint64_t index) const;
  void addVisualFactors(std::uint64_t index, const FrameObservations& frame, FrameResult* result);
  bool tryTriangulate(int id, Track* track);
  // Puts a landmark at p_W into the graph with a factor per observation.
  bool insertLandmark(int id, const Vec3& p_W, Track* track);
  // The reprojection factor of one observation.
  FactorPtr reprojectionFactor(std::uint64_t index, const FeatureObservation& obs) const;
  int rejectOutliers();
  void holdGauge(std::uint64_t index, const Pose& T_WB_before);
  void maintainWindow();
  void marginalizeState(std::uint64_t index, bool keep_landmark_information);
  Pose cameraPose(std::uint64_t index) const;

  VioBackendOptions options_;
  CameraModel camera_;
  Pose T_BC_;
  std::unique_ptr<DynamicsModel> dynamics_;  // of options.method
  SlidingWindowSmoother smoother_;
  std::vector<ImuSample> imu_;
  std::vector<ThrustSample> thrust_;
  std::deque<StateSlot> states_;
  std::map<int, Track> tracks_;
  std::uint64_t next_index_ = 0;
  std::optional<std::uint64_t> last_keyframe_;
};

}  // namespace hdvio
