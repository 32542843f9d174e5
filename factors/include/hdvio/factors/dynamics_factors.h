#pragma once
// The hybrid-dynamics factor of HDVIO and its VIMO / VID-Fusion counterparts: one class per
// dynamics model, all 9-D [r_alpha, r_beta, r_f] with the point-mass rows of
// point_mass_dynamics.h. They differ in the force term r_f and so in their keys:
//   HdvioDynamicsFactor (X_i, V_i, F_i, X_j, V_j, F_j, B_i):
//       r_f = f_j - f_i                        (random walk, sigma = rw * sqrt(dt));
//       its alpha / beta rows take the force linear from f_i to f_j, and the walk's bridge
//       around that line (q dt^5/45, q dt^4/24, q dt^3/12 per axis, q = rw^2) joins their
//       covariance: a loose walk must not claim the thrust model's precision inside the interval
//   VimoDynamicsFactor  (X_i, V_i, F_i, X_j, V_j, B_i):
//       r_f = f_i                              (zero-mean prior, sigma = prior sigma)
//   VidDynamicsFactor   (X_i, V_i, F_i, X_j, V_j, B_i):
//       r_f = f_i - R_i gamma(b_i) / dt        (prior around the mean accelerometer-minus-thrust
//                                               force, rotated to world; uses the accel bias)
// Each declares only the keys its residual depends on. noiseModel() is the real covariance,
// blockdiag(preintegrated [alpha, beta] 6x6 (+ bridge), sigma_f^2 I3), whitened with fixed sizes.
#include <memory>

#include "hdvio/core/factor.h"
#include "hdvio/factors/point_mass_dynamics.h"

namespace hdvio {

class HdvioDynamicsFactor final
    : public FactorT<HdvioDynamicsFactor, 9, PoseVar, Vec3Var, Vec3Var, PoseVar, Vec3Var, Vec3Var,
                     BiasVar>,
      public PointMassDynamics {
 public:
  static constexpr int kNoiseDenseBlock = 6;
  HdvioDynamicsFactor(Key pose_i, Key vel_i, Key force_i, Key pose_j, Key vel_j, Key force_j,
                      Key bias_i, std::shared_ptr<const PreintegratedThrust> pit,
                      const DynamicsFactorParams& params);
  bool evaluateError(const double* const* x, double* residual, double** jacobians) const;
  static NoiseModelPtr noiseFor(const PreintegratedThrust& pit, const DynamicsFactorParams& params);
};

// VIMO and VID-Fusion: keys (X_i, V_i, F_i, X_j, V_j, B_i) and a prior on f_i with
// sigma_f = force_prior_sigma; Derived supplies evaluateError.
template <class Derived>
class ForcePriorDynamicsFactor
    : public FactorT<Derived, 9, PoseVar, Vec3Var, Vec3Var, PoseVar, Vec3Var, BiasVar>,
      public PointMassDynamics {
 public:
  static constexpr int kNoiseDenseBlock = 6;
  ForcePriorDynamicsFactor(Key pose_i, Key vel_i, Key force_i, Key pose_j, Key vel_j, Key bias_i,
                           std::shared_ptr<const PreintegratedThrust> pit,
                           const DynamicsFactorParams& params)
      : FactorT<Derived, 9, PoseVar, Vec3Var, Vec3Var, PoseVar, Vec3Var, BiasVar>(
            {pose_i, vel_i, force_i, pose_j, vel_j, bias_i}, noiseFor(*pit, params)),
        PointMassDynamics(std::move(pit), params.drag) {}
  static NoiseModelPtr noiseFor(const PreintegratedThrust& pit, const DynamicsFactorParams& params) {
    return PointMassDynamics::noiseFor(pit, params, params.force_prior_sigma);
  }
};

class VimoDynamicsFactor final : public ForcePriorDynamicsFactor<VimoDynamicsFactor> {
 public:
  using ForcePriorDynamicsFactor::ForcePriorDynamicsFactor;
  bool evaluateError(const double* const* x, double* residual, double** jacobians) const;
};

class VidDynamicsFactor final : public ForcePriorDynamicsFactor<VidDynamicsFactor> {
 public:
  using ForcePriorDynamicsFactor::ForcePriorDynamicsFactor;
  bool evaluateError(const double* const* x, double* residual, double** jacobians) const;
};

}  // namespace hdvio
