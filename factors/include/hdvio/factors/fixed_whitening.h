#pragma once
// Fixed-size whitening for the preintegration factors, which whiten their own residual and
// Jacobians and hand FactorT a unit noise model. Reason: the dense path of NoiseModel (core)
// uses dynamic-size temporaries, which cost ~2-3 us per 15-D IMU factor evaluation versus
// ~0.4 us for the factor itself (docs/factors.md). The covariance is block diagonal: a dense
// K x K block (the preintegrated part) followed by N - K independent entries (random walks,
// force terms). r_w = S r with S = blockdiag(L^-1, 1/sigma), C_K = L L^T -- the same numbers
// NoiseModel::covariance(C) would produce.
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace hdvio {

template <int N, int K>
class FixedWhitening {
 public:
  static_assert(K > 0 && K < N, "dense block must be a proper leading block");
  using MatN = Eigen::Matrix<double, N, N>;
  using MatK = Eigen::Matrix<double, K, K>;
  using VecD = Eigen::Matrix<double, N - K, 1>;

  FixedWhitening(const MatK& dense_covariance, const VecD& variances) {
    const MatK sym = 0.5 * (dense_covariance + dense_covariance.transpose());
    Eigen::LLT<MatK> llt(sym);
    if (!sym.allFinite() || llt.info() != Eigen::Success || !((variances.array() > 0.0).all()) ||
        !variances.allFinite())
      throw std::invalid_argument("FixedWhitening: covariance is not positive definite");
    sqrt_info_ = llt.matrixL().solve(MatK::Identity());
    sqrt_info_.template triangularView<Eigen::StrictlyUpper>().setZero();
    inv_sigmas_ = variances.cwiseSqrt().cwiseInverse();
    covariance_.setZero();
    covariance_.template topLeftCorner<K, K>() = sym;
    covariance_.template bottomRightCorner<N - K, N - K>().diagonal() = variances;
  }

  void whitenResidual(double* r) const {
    Eigen::Map<Eigen::Matrix<double, N, 1>> v(r);
    const Eigen::Matrix<double, K, 1> head = sqrt_info_.lazyProduct(v.template head<K>());
    v.template head<K>() = head;
    v.template tail<N - K>().array() *= inv_sigmas_.array();
  }

  // J is row-major N x Cols.
  template <int Cols>
  void whitenJacobian(double* J) const {
    Eigen::Map<Eigen::Matrix<double, N, Cols, Eigen::RowMajor>> M(J);
    const Eigen::Matrix<double, K, Cols, Eigen::RowMajor> head =
        sqrt_info_.lazyProduct(M.template topRows<K>());
    M.template topRows<K>() = head;
    M.template bottomRows<N - K>() = inv_sigmas_.asDiagonal() * M.template bottomRows<N - K>();
  }

  const MatN& covariance() const { return covariance_; }

 private:
  MatN covariance_;
  MatK sqrt_info_;  // lower triangular
  VecD inv_sigmas_;
};

}  // namespace hdvio
