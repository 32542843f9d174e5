#pragma once
// Unary priors. PosePrior: r = [p - p0, Log(q0^-1 q)] (the pose tangent convention of lie.h),
// 6-D. VectorPrior<N>: r = x - x0, used as VelocityPrior (V, 3), BiasPrior (B, 6 = [bg, ba]) and
// ForcePrior (F, 3).
#include "hdvio/core/factor.h"

namespace hdvio {

class PosePrior final : public FactorT<PosePrior, 6, PoseVar> {
 public:
  PosePrior(Key pose, const Pose& prior, NoiseModelPtr noise);
  bool evaluateError(const double* const* x, double* residual, double** jacobians) const;
  const Pose& prior() const { return prior_; }

 private:
  Pose prior_;
};

template <int N>
class VectorPrior final : public FactorT<VectorPrior<N>, N, VectorVar<N>> {
 public:
  using VecN = Eigen::Matrix<double, N, 1>;
  VectorPrior(Key key, const VecN& prior, NoiseModelPtr noise)
      : FactorT<VectorPrior<N>, N, VectorVar<N>>({key}, std::move(noise)), prior_(prior) {}
  bool evaluateError(const double* const* x, double* residual, double** jacobians) const {
    Eigen::Map<VecN> r(residual);
    r = Eigen::Map<const VecN>(x[0]) - prior_;
    if (jacobians && jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, N, N, Eigen::RowMajor>> J(jacobians[0]);
      J.setIdentity();
    }
    return true;
  }
  const VecN& prior() const { return prior_; }

 private:
  VecN prior_;
};

using VelocityPrior = VectorPrior<3>;
using BiasPrior = VectorPrior<6>;
using ForcePrior = VectorPrior<3>;

}  // namespace hdvio
