#pragma once
// Options of the visual-inertial(-dynamics) backends, loaded from the `backend` section of an
// experiment YAML (strict: unknown keys are errors).
#include <string>

#include <ceres/types.h>

#include "hdvio/backend/adaptive_force_walk.h"
#include "hdvio/core/ceres_bridge.h"
#include "hdvio/core/config.h"
#include "hdvio/core/model_envelope.h"
#include "hdvio/core/sequence.h"
#include "hdvio/factors/point_mass_dynamics.h"
#include "hdvio/factors/imu_preintegration.h"
#include "hdvio/factors/reprojection_factor.h"
#include "hdvio/factors/thrust_preintegration.h"

namespace hdvio {

// vio: reprojection + IMU. vimo: + point-mass dynamics with a zero-mean external force.
// vid: + external-force mean prior (VID-Fusion). hdvio: + learned residual force.
// The name in the configuration; VioBackend turns it into its DynamicsModel once
// (makeDynamicsModel, dynamics_model.h).
enum class VioMethod { kVio, kVimo, kVid, kHdvio };
VioMethod parseVioMethod(const std::string& name);  // throws std::invalid_argument
std::string toString(VioMethod method);
inline bool usesDynamics(VioMethod m) { return m != VioMethod::kVio; }

// What a keyframe's landmarks put into the prior when the keyframe leaves the window:
// kAll: every observation (VINS-Mono); kKeyframes: their keyframe observations (the prior spans
// the keyframes only); kUntracked: only landmarks no recent state sees leave, the others lose
// the leaving observation (OKVIS). docs/backend.md compares them.
enum class LandmarkMarginalization { kAll, kKeyframes, kUntracked };

struct VioBackendOptions {
  VioMethod method = VioMethod::kVio;
  int num_keyframes = 10;    // L
  int num_recent = 5;        // K most recent states
  // A frame becomes a keyframe when the median parallax to the last keyframe exceeds this
  // (pixels) or when it observes too few of the last keyframe's landmarks.
  double keyframe_parallax_px = 12.0;
  double keyframe_min_tracked_ratio = 0.6;

  double pixel_sigma = 1.0;
  RobustLoss robust_loss = RobustLoss::kHuber;
  double robust_width_px = 2.0;
  double outlier_threshold_px = 6.0;  // reprojection error above which an observation is dropped
  double min_triangulation_angle_deg = 1.0;
  int min_observations = 2;
  // At most this many landmarks in the window (a frontend's feature budget); new landmarks with
  // the longest tracks enter first. Keeps the per-frame cost bounded in rich scenes.
  int max_landmarks = 150;
  LandmarkMarginalization landmark_marginalization = LandmarkMarginalization::kKeyframes;

  int max_iterations = 8;
  double function_tolerance = 1e-5;  // relative cost decrease that ends the solve early
  // Levenberg-Marquardt's damping is 1/radius. The first solve starts at
  // initial_trust_region_radius; with trust_region_warm_start each later solve starts where the
  // previous one ended (within [initial, max]): a well-posed window grows it and then runs nearly
  // Gauss-Newton (1-2 steps where Ceres' default 1e4 took ~4.4), while a poorly constrained one
  // (hover with little parallax) keeps its damping (docs/backend.md).
  double initial_trust_region_radius = 1e4;
  double max_trust_region_radius = 1e8;
  bool trust_region_warm_start = true;
  // Landmarks are eliminated first (Schur complement) unless sparse_normal_cholesky is chosen.
  ceres::LinearSolverType linear_solver = ceres::DENSE_SCHUR;  // or SPARSE_SCHUR, SPARSE_NORMAL_CHOLESKY
  // Schur solvers eliminate exactly the landmarks (fixed 2x3x6 blocks, Ceres' specialized
  // eliminator); false lets Ceres choose the independent set itself.
  bool landmarks_first = true;
  // kCeres: ceres::Solve with linear_solver. kSchurLm: the project's own Levenberg-Marquardt with
  // Ceres' damping rules, landmarks Schur-complemented out (core/schur_lm.h).
  OptimizerOptions::Optimizer optimizer = OptimizerOptions::Optimizer::kCeres;
  double max_solver_time_s = 1e3;  // wall-clock budget; large by default so runs are deterministic

  ImuNoiseParams imu;
  ThrustNoiseParams thrust;
  DynamicsFactorParams dynamics;  // the factor class follows method
  // hdvio: adapt the force walk to the accelerometer's evidence (adaptive_force_walk.h);
  // dynamics.force_random_walk is then its floor.
  AdaptiveForceWalkOptions force_walk_adaptive;
  // hdvio: what the residual-force model saw in training (its weight file's envelope, or the
  // model_* keys). The model's measured error walk holds only where it was measured: a dynamics
  // interval outside gets a walk of at least force_walk_outside_model times its relative
  // distance beyond the envelope (all of it from twice a bound on).
  ModelEnvelope model_envelope;
  double force_walk_outside_model = 5.0;  // m/s^2/sqrt(s)

  // Initial state uncertainty (gauge and biases).
  double init_position_sigma = 1e-3;
  double init_yaw_sigma = 1e-3;
  double init_tilt_sigma = 0.02;
  double init_velocity_sigma = 0.1;
  double init_gyro_bias_sigma = 0.01;
  double init_accel_bias_sigma = 0.1;
  double init_force_sigma = 2.0;
  // hdvio, > 0: the first state's force prior is centred on the accelerometer-minus-model force
  // over this span before it (drag law at the state's velocity) instead of state.f_ext_W. For a
  // guessed start: the walk's only anchor is this prior, and a zero mean in wind made the drag
  // law explain the wind with an invented velocity (docs/backend.md, static start in wind).
  double init_force_window_s = 0.0;
};

// Reads the keys of a `backend:` section; values not given keep their defaults above.
VioBackendOptions loadVioBackendOptions(const ConfigReader& section, VioMethod method);

// The IMU's white-noise densities and bias random walks from the sequence's calibration
// (imu0/sensor.yaml, as OpenVINS and Basalt take them) for each of
// {gyro,accel}_{noise_density,random_walk} that the backend section does not set: the
// experiment's value wins, a calibration value of 0 (not given) keeps the default. Each adopted
// value is recorded in the section's effective configuration.
void adoptImuNoise(const ImuCalibration& calibration, const ConfigReader& section, VioBackendOptions* o);

// The residual-force model's error walk (m/s^2/sqrt(s), measured on held-out flights when it
// was trained; learned/force_model_error.h) as the least walk of the external force: a
// force_random_walk below it (the adaptive walk's floor) is raised to it, and the raised value
// is recorded in the section's effective configuration. The model's uncertainty so reaches
// the dynamics factor whatever the experiment says.
void adoptModelForceWalk(double walk, const ConfigReader& section, VioBackendOptions* o);
// What the residual-force model saw in training (its weight file's envelope): each bound the
// backend section does not set (model_speed_max, model_rate_max, model_thrust_range) is
// adopted and recorded in the section's effective configuration.
void adoptModelEnvelope(const ModelEnvelope& model, const ConfigReader& section, VioBackendOptions* o);
// Defaults for a method (no config).
VioBackendOptions defaultVioBackendOptions(VioMethod method);

}  // namespace hdvio
