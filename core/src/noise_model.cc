#include "hdvio/core/noise_model.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <stdexcept>

namespace hdvio {
namespace {
using RowMatX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
}

std::shared_ptr<const NoiseModel> NoiseModel::isotropic(int dim, double sigma) {
  return diagonal(Eigen::VectorXd::Constant(dim, sigma));
}

std::shared_ptr<const NoiseModel> NoiseModel::diagonal(const Eigen::VectorXd& sigmas) {
  if ((sigmas.array() <= 0.0).any() || !sigmas.allFinite())
    throw std::invalid_argument("NoiseModel::diagonal: sigmas must be positive and finite");
  std::shared_ptr<NoiseModel> m(new NoiseModel());
  m->dim_ = static_cast<int>(sigmas.size());
  m->dense_block_ = 0;
  m->inv_sigmas_ = sigmas.cwiseInverse();
  return m;
}

std::shared_ptr<const NoiseModel> NoiseModel::sqrtInformation(const Eigen::MatrixXd& S) {
  if (S.rows() != S.cols() || !S.allFinite())
    throw std::invalid_argument("NoiseModel::sqrtInformation: need a finite square matrix");
  std::shared_ptr<NoiseModel> m(new NoiseModel());
  m->dim_ = static_cast<int>(S.rows());
  m->dense_block_ = m->dim_;
  m->sqrt_info_ = S;
  return m;
}

std::shared_ptr<const NoiseModel> NoiseModel::information(const Eigen::MatrixXd& I) {
  const Eigen::MatrixXd sym = 0.5 * (I + I.transpose());
  Eigen::LLT<Eigen::MatrixXd> llt(sym);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("NoiseModel::information: matrix is not positive definite");
  // I = L L^T  =>  S = L^T satisfies S^T S = I.
  return sqrtInformation(llt.matrixU());
}

std::shared_ptr<const NoiseModel> NoiseModel::covariance(const Eigen::MatrixXd& C) {
  const Eigen::MatrixXd sym = 0.5 * (C + C.transpose());
  Eigen::LLT<Eigen::MatrixXd> llt(sym);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("NoiseModel::covariance: matrix is not positive definite");
  // C = L L^T  =>  S = L^-1 satisfies S^T S = C^-1.
  const Eigen::MatrixXd L = llt.matrixL();
  return sqrtInformation(
      L.triangularView<Eigen::Lower>().solve(Eigen::MatrixXd::Identity(C.rows(), C.cols())));
}

std::shared_ptr<const NoiseModel> NoiseModel::robust(
    std::shared_ptr<ceres::LossFunction> loss) const {
  std::shared_ptr<NoiseModel> m(new NoiseModel(*this));
  m->loss_ = std::move(loss);
  return m;
}

Eigen::MatrixXd NoiseModel::sqrtInformationMatrix() const {
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(dim_, dim_);
  S.topLeftCorner(dense_block_, dense_block_) = sqrt_info_;
  S.bottomRightCorner(dim_ - dense_block_, dim_ - dense_block_).diagonal() = inv_sigmas_;
  return S;
}

Eigen::MatrixXd NoiseModel::covarianceMatrix() const {
  const int k = dense_block_;
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(dim_, dim_);
  C.bottomRightCorner(dim_ - k, dim_ - k).diagonal() = inv_sigmas_.cwiseAbs2().cwiseInverse();
  if (k == 0) return C;
  if (k < dim_) {
    C.topLeftCorner(k, k) = dense_covariance_;
    return C;
  }
  // Dense: Sigma = S^-1 S^-T.
  const Eigen::MatrixXd S_inv = sqrt_info_.fullPivLu().inverse();
  return S_inv * S_inv.transpose();
}

void NoiseModel::whitenResidual(double* r) const {
  Eigen::Map<Eigen::VectorXd> v(r, dim_);
  const int k = dense_block_;
  if (k > 0) {
    const Eigen::VectorXd head = sqrt_info_ * v.head(k);
    v.head(k) = head;
  }
  v.tail(dim_ - k).array() *= inv_sigmas_.array();
}

void NoiseModel::whitenJacobian(double* J, int cols) const {
  Eigen::Map<RowMatX> M(J, dim_, cols);
  const int k = dense_block_;
  if (k > 0) {
    const RowMatX head = sqrt_info_ * M.topRows(k);
    M.topRows(k) = head;
  }
  M.bottomRows(dim_ - k) = inv_sigmas_.asDiagonal() * M.bottomRows(dim_ - k);
}

}  // namespace hdvio
