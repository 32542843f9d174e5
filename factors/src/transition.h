#pragma once
// The error-state transition shared by IMU and thrust preintegration, applied blockwise:
//   A = [[E^T, 0, 0], [X, I, 0], [dt/2 X, dt I, I]]  over [dtheta, v-like, p-like],
// with X = -dR [f]x dt. A dense 9x9 product would spend most of its work on zero blocks.
#include <Eigen/Core>

#include "hdvio/core/lie.h"

namespace hdvio::detail {

template <int C>
Eigen::Matrix<double, 9, C> applyTransition(const Mat3& Et, const Mat3& X, double dt,
                                            const Eigen::Matrix<double, 9, C>& M) {
  Eigen::Matrix<double, 9, C> out;
  const Eigen::Matrix<double, 3, C> XM = X * M.template topRows<3>();
  out.template topRows<3>().noalias() = Et * M.template topRows<3>();
  out.template middleRows<3>(3) = XM + M.template middleRows<3>(3);
  out.template bottomRows<3>() = (0.5 * dt) * XM + dt * M.template middleRows<3>(3) + M.template bottomRows<3>();
  return out;
}

// A P A^T for symmetric P.
inline Eigen::Matrix<double, 9, 9> propagate(const Mat3& Et, const Mat3& X, double dt,
                                             const Eigen::Matrix<double, 9, 9>& P) {
  const Eigen::Matrix<double, 9, 9> AP = applyTransition<9>(Et, X, dt, P);
  const Eigen::Matrix<double, 9, 9> PAt = AP.transpose();
  return applyTransition<9>(Et, X, dt, PAt);
}

}  // namespace hdvio::detail
