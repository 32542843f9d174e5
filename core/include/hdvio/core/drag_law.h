#pragma once
// Aerodynamic drag of a multirotor as a function of its body-frame velocity u = R^T v and the
// mass-normalized collective thrust T (m/s^2; body axes):
//   f_drag(u, T) = -(D u + D_r s(T) u + C |u| u),   s(T) = sqrt(T / T_hover),  T_hover = 9.81.
// D (1/s) is a constant linear drag, D_r (1/s at hover thrust) the rotor drag of blade flapping
// and induced drag, proportional to the sum of the rotor speeds (Faessler et al. RA-L 2018,
// Kai et al. 2017, Svacha et al. 2017) and so to sqrt(thrust) for equal rotors: written with the
// thrust, the estimator (which has the collective thrust, not always rotor speeds) can evaluate
// it. C (1/m) is parasitic body drag. Shared by the dynamics factor (at the estimated
// velocity), the residual-force trainer and evaluator (at the ground-truth velocity).
#include <algorithm>
#include <cmath>
#include <vector>

#include "hdvio/core/lie.h"

namespace hdvio {

struct DragLaw {
  static constexpr double kHoverThrust = 9.81;  // m/s^2: mass-normalized thrust in hover
  Vec3 linear = Vec3::Zero();     // D, 1/s, body axes
  Vec3 rotor = Vec3::Zero();      // D_r, 1/s at hover thrust, body axes
  Vec3 quadratic = Vec3::Zero();  // C, 1/m, body axes
  double lift = 0.0;              // k_h, 1/m: thrust gained with horizontal speed, + k_h (u_x^2 + u_y^2) on z
  // How far the law is from the measured force, per body axis: a zero-mean Gaussian whose
  // variance grows where the law is least exact (fast, rotating, thrust far from hover),
  //   sigma_a(u, w, T)^2 = sigma_a^2 + (sigma_speed_a |u|)^2 + (sigma_rate_a |w|)^2
  //                        + (sigma_thrust_a (T - T_hover))^2        (m/s^2; w body rate, rad/s),
  // fitted by the Gaussian likelihood of the law's residual (withFittedSigma). The dynamics
  // factor adds it to its covariance (drag_model.h); all zero: the law counts as exact. Not
  // part of enabled().
  Vec3 sigma = Vec3::Zero();         // m/s^2
  Vec3 sigma_speed = Vec3::Zero();   // 1/s: per m/s of body speed
  Vec3 sigma_rate = Vec3::Zero();    // m/s: per rad/s of body rate
  Vec3 sigma_thrust = Vec3::Zero();  // 1: per m/s^2 of thrust away from hover

  bool enabled() const {
    return !linear.isZero(0.0) || !rotor.isZero(0.0) || !quadratic.isZero(0.0) || lift != 0.0;
  }
  bool hasSigma() const {
    return !sigma.isZero(0.0) || !sigma_speed.isZero(0.0) || !sigma_rate.isZero(0.0) || !sigma_thrust.isZero(0.0);
  }
  // True when the sigma depends on speed, rate or thrust (not a constant per axis).
  bool hasVaryingSigma() const {
    return !sigma_speed.isZero(0.0) || !sigma_rate.isZero(0.0) || !sigma_thrust.isZero(0.0);
  }
  Vec3 sigmaAt(const Vec3& u, const Vec3& omega, double thrust) const {
    const double dT = thrust - kHoverThrust;
    return (sigma.cwiseAbs2() + u.squaredNorm() * sigma_speed.cwiseAbs2() +
            omega.squaredNorm() * sigma_rate.cwiseAbs2() + (dT * dT) * sigma_thrust.cwiseAbs2())
        .cwiseSqrt();
  }
  // s(T): the rotor-speed sum relative to hover (negative thrust counts as none).
  static double rotorScale(double thrust) { return std::sqrt(std::max(thrust, 0.0) / kHoverThrust); }
  // Per-axis linear coefficient at thrust T: D + D_r s(T).
  Vec3 linearAt(double thrust) const { return linear + rotorScale(thrust) * rotor; }
  Vec3 force(const Vec3& u, double thrust) const {
    Vec3 f = -(linearAt(thrust).cwiseProduct(u) + u.norm() * quadratic.cwiseProduct(u));
    f.z() += lift * (u.x() * u.x() + u.y() * u.y());
    return f;
  }
  Mat3 jacobian(const Vec3& u, double thrust) const {  // d force / d u (the thrust is an input)
    Mat3 J = linearAt(thrust).asDiagonal();
    const double speed = u.norm();
    // d(|u| u)/du = |u| I + u u^T / |u|; both terms vanish at u = 0.
    if (speed > 1e-9)
      J += quadratic.asDiagonal() * (speed * Mat3::Identity() + u * u.transpose() / speed);
    J(2, 0) -= 2.0 * lift * u.x();
    J(2, 1) -= 2.0 * lift * u.y();
    return -J;
  }
};

// The coefficients a fit may use; the others stay zero.
struct DragTerms {
  bool linear = true, rotor = false, quadratic = true, lift = false;
};

// Fits the chosen coefficients (non-negative, per axis, least squares) to force samples
// f_k ~ drag(u_k, T_k): body-frame velocities u_k, collective thrusts T_k (m/s^2; only read with
// terms.rotor) and the mass-normalized force the law should explain (specific force minus
// thrust). Non-negative because a flight that barely excites an axis can otherwise give an
// unphysical negative coefficient. Throws std::invalid_argument if the vectors differ in
// length or hold fewer than 100 samples, or if no term is chosen.
DragLaw fitDragLaw(const std::vector<Vec3>& u_body, const std::vector<double>& thrust,
                   const std::vector<Vec3>& force, const DragTerms& terms = {});

// The sigma parts a fit may use besides the constant one.
struct DragSigmaTerms {
  bool speed = false, rate = false, thrust = false;
};

// The law with its sigma (constant and the chosen terms) fitted to the same kind of samples as
// fitDragLaw plus body rates, by maximum likelihood of the law's residual f_k - law.force(u_k,
// T_k) under N(0, sigma(u_k, w_k, T_k)^2) per axis (Fisher scoring on the log coefficients,
// deterministic). With no term it is the residual's RMS. Throws std::invalid_argument if the
// vectors differ in length or hold fewer than 100 samples.
DragLaw withFittedSigma(DragLaw law, const std::vector<Vec3>& u_body, const std::vector<Vec3>& omega,
                        const std::vector<double>& thrust, const std::vector<Vec3>& force,
                        const DragSigmaTerms& terms = {});

}  // namespace hdvio
