#pragma once
// Hybrid-dynamics factor (HDVIO Eqs. 4-6) and its VIMO / VID-Fusion variants, 9-D, ordered
// [r_alpha, r_beta, r_f] over keys (X_i, V_i, F_i, X_j, V_j, F_j, B_i):
//   r_alpha = R_i^T (p_j - p_i - v_i dt - 1/2 (g + f_i) dt^2) - (alpha + dalpha_dbg dbg)
//   r_beta  = R_i^T (v_j - v_i - (g + f_i) dt)               - (beta  + dbeta_dbg dbg)
// f_i is the external force (world frame) held constant over [i, j]; dbg = bg_i - bg used for
// preintegration. With a drag model (drag_model.h) the integrated drag at the velocities
// R_i^T v_i, R_i^T v_j is added to alpha and beta. The force term depends on the variant:
//   kHdvio:     r_f = f_j - f_i                         (random walk, sigma = rw * sqrt(dt))
//   kVimo:      r_f = f_i                               (zero-mean prior, sigma = prior sigma)
//   kVidFusion: r_f = f_i - R_i gamma(b_i) / dt         (prior around the mean accelerometer-
//                                                        minus-thrust force, rotated to world)
// The (alpha, beta) block is weighted by the preintegrated 6x6 covariance, r_f by w_f = 1/sigma^2;
// the factor whitens itself (fixed_whitening.h): noiseModel() is unit, covariance() the real one.
// Only kHdvio touches F_j (its Jacobian is zero otherwise); only kVidFusion uses the accel bias.
#include <memory>

#include "hdvio/core/factor.h"
#include "hdvio/factors/drag_model.h"
#include "hdvio/factors/fixed_whitening.h"
#include "hdvio/factors/thrust_preintegration.h"

namespace hdvio {

enum class DynamicsVariant { kHdvio, kVimo, kVidFusion };

struct DynamicsFactorParams {
  DynamicsVariant variant = DynamicsVariant::kHdvio;
  double force_random_walk = 1.0;  // kHdvio: m/s^2/sqrt(s)
  double force_prior_sigma = 1.0;  // kVimo / kVidFusion: m/s^2
  DragLaw drag;                  // none by default (the paper's point-mass model)
};

class DynamicsFactor final : public FactorT<DynamicsFactor, 9, PoseVar, Vec3Var, Vec3Var, PoseVar,
                                            Vec3Var, Vec3Var, BiasVar> {
 public:
  DynamicsFactor(Key pose_i, Key vel_i, Key force_i, Key pose_j, Key vel_j, Key force_j, Key bias_i,
                 std::shared_ptr<const PreintegratedThrust> pit, const DynamicsFactorParams& params);

  bool evaluateError(const double* const* x, double* residual, double** jacobians) const;
  const PreintegratedThrust& preintegrated() const { return *pit_; }
  DynamicsVariant variant() const { return variant_; }
  const Eigen::Matrix<double, 9, 9>& covariance() const { return whitening_.covariance(); }
  static Eigen::Matrix<double, 9, 9> covarianceFor(const PreintegratedThrust& pit,
                                                   const DynamicsFactorParams& params);

 private:
  std::shared_ptr<const PreintegratedThrust> pit_;
  DynamicsVariant variant_;
  DragLaw drag_;
  FixedWhitening<9, 6> whitening_;
};

}  // namespace hdvio
