#pragma once
// The Model-EKF's quadrotor model with collective thrust and linear rotor drag (body frame):
//   v' = R (k T - D R^T v) + g,   p' = v
// (T: mass-normalized collective thrust, k: thrust scale, D = diag(d): linear drag). The drag
// term makes the model's displacement depend on the velocity, which is what lets the filter
// learn velocity from it; without it (D = 0) the model is dead reckoning with the thrust in
// place of the accelerometer. k and d are fitted on training flights by least squares against
// the accelerometer (specific force f = k T - D v_body). docs/imo.md.
#include <memory>
#include <vector>

#include "hdvio/backend/imo/displacement_source.h"
#include "hdvio/core/drag_law.h"
#include "hdvio/core/sequence.h"

namespace hdvio::imo {

// The drag is the project's one drag law type (core/drag_law.h) with only its linear term: the
// Model-EKF's displacement is linear in the velocity (makeDragModelSource rejects a quadratic).
struct DragModel {
  double thrust_scale = 1.0;  // k
  DragLaw drag;               // drag.linear = d (1/s), body axes; drag.rotor = drag.quadratic = 0
};

// One training sample: specific force and thrust (body), ground-truth body velocity and attitude.
struct DragSample {
  Vec3 specific_force = Vec3::Zero();
  Vec3 thrust = Vec3::Zero();
  Vec3 velocity_body = Vec3::Zero();
  Mat3 R = Mat3::Identity();  // world from body
};

// Samples at every IMU time inside the thrust and ground-truth spans (thrust and ground truth
// interpolated). Ground truth needs velocities (InputError otherwise).
std::vector<DragSample> collectDragSamples(const Sequence& seq, const std::vector<ThrustSample>& thrust);

struct DragFit {
  DragModel model;
  std::size_t samples = 0;
  // World-frame residual R (f - model) per axis, mean and RMS, for the thrust-only model
  // (k = 1, d = 0) and the fitted one.
  Vec3 mean_thrust_only = Vec3::Zero(), rms_thrust_only = Vec3::Zero();
  Vec3 mean_fitted = Vec3::Zero(), rms_fitted = Vec3::Zero();
};

// Least squares over all samples: k (if fit_thrust_scale, else 1) and d_x, d_y, d_z.
// Throws InputError with fewer than 100 samples.
DragFit fitDragModel(const std::vector<DragSample>& samples, bool fit_thrust_scale);

// For the hybrid dynamics of the visual methods (backend.drag_linear / drag_quadratic): the full
// drag law f - k T = -(D u + C |u| u) (u = body velocity) with the thrust scale k held fixed,
// fitted by core's fitDragLaw on the samples. rms: world-frame residual per axis.
struct DragLawFit {
  DragLaw law;
  Vec3 rms = Vec3::Zero();
};
DragLawFit fitDragLawOnSamples(const std::vector<DragSample>& samples, double thrust_scale);

// The Model-EKF measurement of the drag model. Over the window, from the begin clone,
//   p_end - p_begin = C v_begin + d,
// exactly (the model is linear in v); C = W I for D = 0. The source returns z = d with
// velocity_matrix C, i.e. the measurement z = p_j - p_i - C v_i, and (when
// attitude_jacobian) the derivative of C v_i + d with respect to the begin clone's attitude
// error, because the model's thrust direction depends on it exactly as the IMU prediction does.
// Integration: midpoint steps of about step_s, thrust interpolated at their midpoints.
// thrust shared: it may grow while the source lives (a streaming estimator's buffer); windows
// it does not cover yet get no estimate.
DisplacementSource makeDragModelSource(std::shared_ptr<const std::vector<ThrustSample>> thrust,
                                       const DragModel& model, double step_s, const Vec3& sigma,
                                       const Vec3& gravity, bool attitude_jacobian);
DisplacementSource makeDragModelSource(std::vector<ThrustSample> thrust, const DragModel& model,
                                       double step_s, const Vec3& sigma, const Vec3& gravity,
                                       bool attitude_jacobian);

}  // namespace hdvio::imo
