#pragma once
// A test factor for small bundle-adjustment problems: a landmark seen in the body frame of a
// pose, r = R^T (l - p) - z (3 rows; tangent Jacobians of the pose [dp, dtheta] and the point).
#include "hdvio/core/factor.h"
#include "hdvio/core/lie.h"

namespace hdvio {
namespace testing {

class PointInBodyFactor : public FactorT<PointInBodyFactor, 3, PoseVar, Vec3Var> {
 public:
  PointInBodyFactor(Key pose, Key landmark, const Vec3& z, NoiseModelPtr noise)
      : FactorT({pose, landmark}, std::move(noise)), z_(z) {}
  bool evaluateError(const double* const* x, double* residual, double** J) const {
    const Eigen::Map<const Vec3> p(x[0]), l(x[1]);
    const Mat3 R = Eigen::Map<const Quat>(x[0] + 3).toRotationMatrix();
    const Vec3 b = R.transpose() * (l - p);
    Eigen::Map<Vec3> r(residual);
    r = b - z_;
    if (!J) return true;
    using J36 = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;
    using J33 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
    if (J[0]) {
      Eigen::Map<J36> Jx(J[0]);
      Jx.leftCols<3>() = -R.transpose();
      Jx.rightCols<3>() = hat(b);
    }
    if (J[1]) {
      Eigen::Map<J33> Jl(J[1]);
      Jl = R.transpose();
    }
    return true;
  }

 private:
  Vec3 z_;
};

}  // namespace testing
}  // namespace hdvio
