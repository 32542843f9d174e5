#pragma once
// The part the three dynamics factors (dynamics_factors.h) share: the preintegrated thrust of
// one interval, the optional drag law at the state's velocity (drag_model.h), and the 6-D
// point-mass residual (HDVIO Eqs. 4-5), rows 0-5 of each factor:
//   r_alpha = R_i^T (p_j - p_i - v_i dt - 1/2 (g + f_i) dt^2) - (alpha + dalpha_dbg dbg) - alpha_drag
//   r_beta  = R_i^T (v_j - v_i - (g + f_i) dt)               - (beta  + dbeta_dbg dbg)  - beta_drag
// f_i is the external force (world frame) held constant over [i, j] (HdvioDynamicsFactor adds
// its interpolation to f_j on top); dbg = bg_i - bg used for
// preintegration. Its covariance is the preintegrated [alpha, beta] block.
#include <memory>

#include "hdvio/core/lie.h"
#include "hdvio/core/noise_model.h"
#include "hdvio/factors/drag_model.h"
#include "hdvio/factors/thrust_preintegration.h"

namespace hdvio {

// Noise settings of the force rows (each factor reads the one it needs) and the drag law.
struct DynamicsFactorParams {
  double force_random_walk = 1.0;  // HDVIO: m/s^2/sqrt(s)
  double force_prior_sigma = 1.0;  // VIMO / VID-Fusion: m/s^2
  DragLaw drag;                    // none by default (the paper's point-mass model)
  // Body-frame velocities (frame i) at which the law's sigma is evaluated when it grows with
  // speed: the prediction when the factor is made. The weight stays fixed for the factor's
  // life, like every noise model here (a state-dependent weight would make the cost
  // non-Gaussian and the marginalization's prior inexact).
  Vec3 sigma_velocity_i = Vec3::Zero(), sigma_velocity_j = Vec3::Zero();
};

class PointMassDynamics {
 public:
  // Ambient parameter blocks, in the factors' own key order.
  struct Inputs {
    const double* pose_i;
    const double* vel_i;
    const double* force_i;
    const double* pose_j;
    const double* vel_j;
    const double* bias_i;
  };
  // Tangent Jacobians of the 9-D factor (row-major 9 x n; null: not wanted). evaluate() writes
  // rows 0-5 of each and zeroes rows 6-8 of all but force_i, whose rows 6-8 are the caller's.
  struct Jacobians {
    double* pose_i = nullptr;
    double* vel_i = nullptr;
    double* force_i = nullptr;
    double* pose_j = nullptr;
    double* vel_j = nullptr;
    double* bias_i = nullptr;
  };

  PointMassDynamics(std::shared_ptr<const PreintegratedThrust> pit, const DragLaw& drag);
  // blockdiag(preintegrated [alpha, beta] 6x6 + the drag law's dragCovariance at the params'
  // sigma velocities, sigma_f^2 I3); throws std::invalid_argument unless sigma_f is positive
  // and finite.
  static std::shared_ptr<const NoiseModel> noiseFor(const PreintegratedThrust& pit,
                                                    const DynamicsFactorParams& params, double sigma_f);
  const PreintegratedThrust& preintegrated() const { return *pit_; }
  // Rows 0-5 of residual (9 entries); returns R_i for the caller's force rows.
  Mat3 evaluate(const Inputs& x, double* residual, const Jacobians* jacobians) const;

 private:
  std::shared_ptr<const PreintegratedThrust> pit_;
  DragLaw drag_;
};

}  // namespace hdvio
