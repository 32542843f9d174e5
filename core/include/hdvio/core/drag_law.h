#pragma once
// Aerodynamic drag of a multirotor as a function of its body-frame velocity u = R^T v
// (mass-normalized, body axes): f_drag(u) = -(D u + C |u| u) with diagonal D (rotor drag, 1/s;
// Faessler et al. RA-L 2018) and C (parasitic body drag, 1/m). Shared by the dynamics factor
// (evaluated at the estimated velocity) and the residual-force trainer (which learns what it
// leaves, at the ground-truth velocity).
#include <vector>

#include "hdvio/core/lie.h"

namespace hdvio {

struct DragLaw {
  Vec3 linear = Vec3::Zero();     // D, 1/s, body axes
  Vec3 quadratic = Vec3::Zero();  // C, 1/m, body axes

  bool enabled() const { return !linear.isZero(0.0) || !quadratic.isZero(0.0); }
  Vec3 force(const Vec3& u) const {
    return -(linear.cwiseProduct(u) + u.norm() * quadratic.cwiseProduct(u));
  }
  Mat3 jacobian(const Vec3& u) const {  // d force / d u
    Mat3 J = linear.asDiagonal();
    const double speed = u.norm();
    // d(|u| u)/du = |u| I + u u^T / |u|; both terms vanish at u = 0.
    if (speed > 1e-9)
      J += quadratic.asDiagonal() * (speed * Mat3::Identity() + u * u.transpose() / speed);
    return -J;
  }
};

// Fits D and C (non-negative, per axis, least squares) to force samples f_k ~ drag(u_k):
// body-frame velocities u_k and the mass-normalized force the law should explain (specific
// force minus thrust). Non-negative because a flight that barely excites an axis can
// otherwise give an unphysical negative coefficient. Throws std::invalid_argument if the
// vectors differ in length or hold fewer than 100 samples.
DragLaw fitDragLaw(const std::vector<Vec3>& u_body, const std::vector<Vec3>& force);

}  // namespace hdvio
