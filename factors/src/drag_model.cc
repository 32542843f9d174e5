#include "hdvio/factors/drag_model.h"

#include "hdvio/factors/thrust_preintegration.h"

namespace hdvio {

DragIntegral integrateDrag(const PreintegratedThrust& pit, const DragLaw& drag, const Vec3& u_i,
                           const Vec3& u_j) {
  DragIntegral out;
  if (!drag.enabled()) return out;
  for (const PreintegratedThrust::DragNode& n : pit.dragNodes()) {
    const Vec3 u = n.dR.transpose() * ((1.0 - n.s) * u_i + n.s * u_j);
    const Vec3 m = n.dR * drag.force(u, n.thrust);
    const Mat3 J = n.dR * drag.jacobian(u, n.thrust) * n.dR.transpose();  // d m / d(interpolated u_i)
    out.beta += n.w_beta * m;
    out.alpha += n.w_alpha * m;
    out.dbeta_dui += (n.w_beta * (1.0 - n.s)) * J;
    out.dbeta_duj += (n.w_beta * n.s) * J;
    out.dalpha_dui += (n.w_alpha * (1.0 - n.s)) * J;
    out.dalpha_duj += (n.w_alpha * n.s) * J;
  }
  return out;
}

Mat6 dragCovariance(const PreintegratedThrust& pit, const DragLaw& drag, const Vec3& u_i, const Vec3& u_j) {
  if (!drag.enabled() || !drag.hasSigma()) return Mat6::Zero();
  Eigen::Matrix<double, 6, 3> B = Eigen::Matrix<double, 6, 3>::Zero();
  if (!drag.hasVaryingSigma()) {  // one sigma for the interval: diag(sigma) factors out
    for (const PreintegratedThrust::DragNode& n : pit.dragNodes()) {
      B.topRows<3>() += n.w_alpha * n.dR;
      B.bottomRows<3>() += n.w_beta * n.dR;
    }
    return B * drag.sigma.cwiseAbs2().asDiagonal() * B.transpose();
  }
  for (const PreintegratedThrust::DragNode& n : pit.dragNodes()) {
    const Vec3 u = n.dR.transpose() * ((1.0 - n.s) * u_i + n.s * u_j);
    const Mat3 S = n.dR * drag.sigmaAt(u, n.omega, n.thrust).asDiagonal();
    B.topRows<3>() += n.w_alpha * S;
    B.bottomRows<3>() += n.w_beta * S;
  }
  return B * B.transpose();
}

}  // namespace hdvio
