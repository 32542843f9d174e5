#pragma once
// Drag at the state's velocity (core/drag_law.h) in the hybrid dynamics: unlike the learned
// residual force (a function of the thrust and gyro history), it is evaluated at the estimated
// velocity inside the dynamics factor, so the accelerometer-minus-thrust difference carries
// information about the velocity itself.
//
// Integrated over a dynamics interval [i, j] with the velocity linear in time between the
// keyframes' estimates and the body rotation of the preintegration (gyro bias held at its
// linearization point, as for the thrust):
//   beta_drag  = sum_k w_beta,k  dR_k f_drag(dR_k^T ((1 - s_k) u_i + s_k u_j)),  u_i = R_i^T v_i,
//   alpha_drag = sum_k w_alpha,k dR_k f_drag(...)                                u_j = R_i^T v_j,
// with the nodes (dR_k, s_k, weights) recorded by the thrust preintegration.
#include "hdvio/core/drag_law.h"

namespace hdvio {

class PreintegratedThrust;

struct DragIntegral {
  Vec3 alpha = Vec3::Zero(), beta = Vec3::Zero();  // frame i, added to the preintegrated deltas
  Mat3 dalpha_dui = Mat3::Zero(), dalpha_duj = Mat3::Zero();
  Mat3 dbeta_dui = Mat3::Zero(), dbeta_duj = Mat3::Zero();
};

DragIntegral integrateDrag(const PreintegratedThrust& pit, const DragLaw& drag, const Vec3& u_i,
                           const Vec3& u_j);

// Covariance of [alpha_drag, beta_drag] (6x6, frame i) from the law's sigma, taken as one
// standard-normal error z in the body frame held over the interval (the law misses slowly
// varying aerodynamics, not white noise) and scaled at each node by the sigma there, evaluated
// at the velocities u_i, u_j (frame i, as in integrateDrag), the node's body rate and thrust:
// B B^T with B = [sum_k w_alpha,k dR_k diag(sigma_k); sum_k w_beta,k dR_k diag(sigma_k)].
// Zero without a law or a sigma.
Mat6 dragCovariance(const PreintegratedThrust& pit, const DragLaw& drag, const Vec3& u_i, const Vec3& u_j);

}  // namespace hdvio
