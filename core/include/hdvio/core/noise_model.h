#pragma once
// Gaussian noise models as square-root information matrices (r_whitened = S r, with
// S^T S = Sigma^-1), plus an optional robust loss applied to the whitened residual.
#include <memory>

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

  // The same Gaussian with a robust loss on the whitened residual (Huber, Cauchy, ...).
  std::shared_ptr<const NoiseModel> robust(std::shared_ptr<ceres::LossFunction> loss) const;

  int dim() const { return dim_; }
  bool isDiagonal() const { return diagonal_; }
  Eigen::MatrixXd sqrtInformationMatrix() const;
  ceres::LossFunction* loss() const { return loss_.get(); }

  // In place: r <- S r (length dim) and J <- S J (row-major, dim x cols).
  void whitenResidual(double* r) const;
  void whitenJacobian(double* J, int cols) const;

 private:
  NoiseModel() = default;
  int dim_ = 0;
  bool diagonal_ = true;
  Eigen::VectorXd inv_sigmas_;     // diagonal case
  Eigen::MatrixXd sqrt_info_;      // dense case
  std::shared_ptr<ceres::LossFunction> loss_;
};

using NoiseModelPtr = std::shared_ptr<const NoiseModel>;

}  // namespace hdvio
