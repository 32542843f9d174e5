#pragma once
// A relative-pose factor used to exercise the core framework (FactorT, manifolds, bridge).
// r = [R_i^T (p_j - p_i) - p_z,  Log(q_z^-1 q_i^-1 q_j)], analytic Jacobians in the hdvio
// tangent convention.
#include "hdvio/core/factor.h"
#include "hdvio/core/lie.h"

namespace hdvio::testing {

class BetweenPoseFactor : public FactorT<BetweenPoseFactor, 6, PoseVar, PoseVar> {
 public:
  BetweenPoseFactor(Key i, Key j, const Pose& measured, NoiseModelPtr noise)
      : FactorT({i, j}, std::move(noise)), z_(measured) {}

  bool evaluateError(const double* const* x, double* residual, double** J) const {
    const Eigen::Map<const Vec3> pi(x[0]), pj(x[1]);
    const Eigen::Map<const Quat> qi(x[0] + 3), qj(x[1] + 3);
    const Mat3 Ri = qi.toRotationMatrix();
    const Vec3 dp_body = Ri.transpose() * (pj - pi);
    const Vec3 rtheta = quatLog(z_.q.conjugate() * qi.conjugate() * qj);
    Eigen::Map<Vec6> r(residual);
    r << dp_body - z_.p, rtheta;
    if (!J) return true;
    using J66 = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;
    const Mat3 Jr_inv = rightJacobianInverse(rtheta);
    if (J[0]) {
      Eigen::Map<J66> Ji(J[0]);
      Ji.setZero();
      Ji.topLeftCorner<3, 3>() = -Ri.transpose();
      Ji.topRightCorner<3, 3>() = hat(dp_body);
      Ji.bottomRightCorner<3, 3>() = -Jr_inv * qj.toRotationMatrix().transpose() * Ri;
    }
    if (J[1]) {
      Eigen::Map<J66> Jj(J[1]);
      Jj.setZero();
      Jj.topLeftCorner<3, 3>() = Ri.transpose();
      Jj.bottomRightCorner<3, 3>() = Jr_inv;
    }
    return true;
  }

 private:
  Pose z_;
};

class PosePriorFactor : public FactorT<PosePriorFactor, 6, PoseVar> {
 public:
  PosePriorFactor(Key k, const Pose& prior, NoiseModelPtr noise)
      : FactorT({k}, std::move(noise)), prior_(prior) {}
  bool evaluateError(const double* const* x, double* residual, double** J) const {
    const Pose pose(Eigen::Map<const Quat>(x[0] + 3), Eigen::Map<const Vec3>(x[0]));
    Eigen::Map<Vec6> r(residual);
    r = pose.minus(prior_);
    if (J && J[0]) {
      Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> J0(J[0]);
      J0.setIdentity();
      J0.bottomRightCorner<3, 3>() = rightJacobianInverse(r.tail<3>());
    }
    return true;
  }

 private:
  Pose prior_;
};

}  // namespace hdvio::testing
