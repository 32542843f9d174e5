#pragma once
// IMU factor between (X_i, V_i, B_i) and (X_j, V_j, B_j): Forster's preintegrated residual plus
// the bias random walk, 15-D, ordered [r_R, r_v, r_p, r_bg, r_ba]:
//   r_R  = Log( (dR Exp(dR_dbg dbg))^T R_i^T R_j )
//   r_v  = R_i^T (v_j - v_i - g dt) - (dv + dv_dbg dbg + dv_dba dba)
//   r_p  = R_i^T (p_j - p_i - v_i dt - 1/2 g dt^2) - (dp + dp_dbg dbg + dp_dba dba)
//   r_b  = b_j - b_i
// with db = b_i - (preintegration bias). Covariance: blockdiag(preintegrated 9x9,
// sigma_bg_rw^2 dt I, sigma_ba_rw^2 dt I): noiseModel() is that block-diagonal model, whitened
// with fixed sizes (kNoiseDenseBlock). BiasBetweenFactor is the random walk on its own, for
// graphs that integrate the IMU elsewhere.
#include <memory>

#include "hdvio/core/factor.h"
#include "hdvio/factors/imu_preintegration.h"

namespace hdvio {

class ImuFactor final : public FactorT<ImuFactor, 15, PoseVar, Vec3Var, BiasVar, PoseVar, Vec3Var,
                                       BiasVar> {
 public:
  static constexpr int kNoiseDenseBlock = 9;
  ImuFactor(Key pose_i, Key vel_i, Key bias_i, Key pose_j, Key vel_j, Key bias_j,
            std::shared_ptr<const PreintegratedImu> pim);

  bool evaluateError(const double* const* x, double* residual, double** jacobians) const;
  const PreintegratedImu& preintegrated() const { return *pim_; }
  static NoiseModelPtr noiseFor(const PreintegratedImu& pim);

 private:
  std::shared_ptr<const PreintegratedImu> pim_;
};

class BiasBetweenFactor final : public FactorT<BiasBetweenFactor, 6, BiasVar, BiasVar> {
 public:
  // Random walk over dt seconds with the densities of params.
  BiasBetweenFactor(Key bias_i, Key bias_j, double dt, const ImuNoiseParams& params);
  bool evaluateError(const double* const* x, double* residual, double** jacobians) const;
};

}  // namespace hdvio
