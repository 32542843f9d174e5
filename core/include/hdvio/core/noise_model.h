#pragma once
// Gaussian noise models as square-root information matrices (r_whitened = S r, with
// S^T S = Sigma^-1), plus an optional robust loss applied to the whitened residual.
//
// Three shapes: diagonal, dense, and block diagonal (a dense K x K leading block followed by
// N - K independent entries, the shape of the preintegration factors' covariance). A block
// model can also whiten with compile-time sizes (whitenResidualFixed / whitenJacobianFixed):
// the dynamic-size dense path costs ~2-3 us per 15-D IMU factor in heap temporaries versus
// ~0.4 us for the factor itself (docs/factors.md). FactorT picks that path when the factor
// declares kNoiseDenseBlock, so a factor's noiseModel() is always its real covariance.
#include <memory>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <ceres/loss_function.h>

namespace hdvio {

class NoiseModel {
 public:
  static std::shared_ptr<const NoiseModel> isotropic(int dim, double sigma);
  static std::shared_ptr<const NoiseModel> diagonal(const Eigen::VectorXd& sigmas);
  static std::shared_ptr<const NoiseModel> sqrtInformation(const Eigen::MatrixXd& S);
  static std::shared_ptr<const NoiseModel> covariance(const Eigen::MatrixXd& C);
  static std::shared_ptr<const NoiseModel> information(const Eigen::MatrixXd& I);
  // Covariance blockdiag(dense, diag(variances)); dense is K x K, N = K + variances.size().
  // Computed with fixed sizes so that the fixed-size whitening below is exact and cheap.
  template <int N, int K>
  static std::shared_ptr<const NoiseModel> blockDiagonal(const Eigen::Matrix<double, K, K>& dense,
                                                         const Eigen::Matrix<double, N - K, 1>& variances);

  // The same Gaussian with a robust loss on the whitened residual (Huber, Cauchy, ...).
  std::shared_ptr<const NoiseModel> robust(std::shared_ptr<ceres::LossFunction> loss) const;

  int dim() const { return dim_; }
  bool isDiagonal() const { return dense_block_ == 0; }
  // Size of the leading dense block: 0 diagonal, dim() dense, in between block diagonal.
  int denseBlock() const { return dense_block_; }
  Eigen::MatrixXd sqrtInformationMatrix() const;
  // Sigma = (S^T S)^-1; exact (the numbers given) for diagonal and block-diagonal models.
  Eigen::MatrixXd covarianceMatrix() const;
  ceres::LossFunction* loss() const { return loss_.get(); }

  // In place: r <- S r (length dim) and J <- S J (row-major, dim x cols).
  void whitenResidual(double* r) const;
  void whitenJacobian(double* J, int cols) const;
  // The same for a block model with dim() == N and denseBlock() == K (checked by the caller
  // once, e.g. FactorT's constructor), without heap temporaries.
  template <int N, int K>
  void whitenResidualFixed(double* r) const;
  template <int N, int K, int Cols>
  void whitenJacobianFixed(double* J) const;
  // A diagonal model (denseBlock() == 0) with dim() == N: the same products as the dynamic path
  // (each entry times its row's 1/sigma), with compile-time sizes.
  template <int N>
  void whitenResidualDiagonal(double* r) const;
  template <int N, int Cols>
  void whitenJacobianDiagonal(double* J) const;

 private:
  NoiseModel() = default;
  int dim_ = 0;
  int dense_block_ = 0;
  Eigen::VectorXd inv_sigmas_;     // the dim - dense_block diagonal entries
  Eigen::MatrixXd sqrt_info_;      // dense_block x dense_block (lower triangular for block models)
  Eigen::MatrixXd dense_covariance_;  // block models: the dense block as given (symmetrized)
  std::shared_ptr<ceres::LossFunction> loss_;
};

using NoiseModelPtr = std::shared_ptr<const NoiseModel>;

template <int N, int K>
std::shared_ptr<const NoiseModel> NoiseModel::blockDiagonal(
    const Eigen::Matrix<double, K, K>& dense, const Eigen::Matrix<double, N - K, 1>& variances) {
  static_assert(K > 0 && K < N, "dense block must be a proper leading block");
  using MatK = Eigen::Matrix<double, K, K>;
  const MatK sym = 0.5 * (dense + dense.transpose());
  Eigen::LLT<MatK> llt(sym);
  if (!sym.allFinite() || llt.info() != Eigen::Success || !((variances.array() > 0.0).all()) ||
      !variances.allFinite())
    throw std::invalid_argument("NoiseModel::blockDiagonal: covariance is not positive definite");
  // C_K = L L^T  =>  S_K = L^-1.
  MatK sqrt_info = llt.matrixL().solve(MatK::Identity());
  sqrt_info.template triangularView<Eigen::StrictlyUpper>().setZero();
  std::shared_ptr<NoiseModel> m(new NoiseModel());
  m->dim_ = N;
  m->dense_block_ = K;
  m->sqrt_info_ = sqrt_info;
  m->inv_sigmas_ = variances.cwiseSqrt().cwiseInverse();
  m->dense_covariance_ = sym;
  return m;
}

template <int N, int K>
void NoiseModel::whitenResidualFixed(double* r) const {
  Eigen::Map<Eigen::Matrix<double, N, 1>> v(r);
  const Eigen::Map<const Eigen::Matrix<double, K, K>> S(sqrt_info_.data());
  const Eigen::Map<const Eigen::Matrix<double, N - K, 1>> inv_sigmas(inv_sigmas_.data());
  const Eigen::Matrix<double, K, 1> head = S.lazyProduct(v.template head<K>());
  v.template head<K>() = head;
  v.template tail<N - K>().array() *= inv_sigmas.array();
}

template <int N, int K, int Cols>
void NoiseModel::whitenJacobianFixed(double* J) const {
  Eigen::Map<Eigen::Matrix<double, N, Cols, Eigen::RowMajor>> M(J);
  const Eigen::Map<const Eigen::Matrix<double, K, K>> S(sqrt_info_.data());
  const Eigen::Map<const Eigen::Matrix<double, N - K, 1>> inv_sigmas(inv_sigmas_.data());
  const Eigen::Matrix<double, K, Cols, Eigen::RowMajor> head = S.lazyProduct(M.template topRows<K>());
  M.template topRows<K>() = head;
  M.template bottomRows<N - K>() = inv_sigmas.asDiagonal() * M.template bottomRows<N - K>();
}

template <int N>
void NoiseModel::whitenResidualDiagonal(double* r) const {
  Eigen::Map<Eigen::Matrix<double, N, 1>> v(r);
  v.array() *= Eigen::Map<const Eigen::Matrix<double, N, 1>>(inv_sigmas_.data()).array();
}

template <int N, int Cols>
void NoiseModel::whitenJacobianDiagonal(double* J) const {
  Eigen::Map<Eigen::Matrix<double, N, Cols, Eigen::RowMajor>> M(J);
  M = Eigen::Map<const Eigen::Matrix<double, N, 1>>(inv_sigmas_.data()).asDiagonal() * M;
}

}  // namespace hdvio
