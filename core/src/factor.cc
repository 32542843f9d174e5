#include "hdvio/core/factor.h"

#include <stdexcept>
#include <vector>

namespace hdvio {

Factor::Factor(std::vector<Key> keys, NoiseModelPtr noise)
    : keys_(std::move(keys)), noise_(std::move(noise)) {
  if (!noise_) throw std::invalid_argument("Factor: null noise model");
}

bool Factor::whitenedError(const Values& values, Eigen::VectorXd* residual) const {
  std::vector<const double*> params;
  for (Key k : keys_) params.push_back(values.data(k));
  residual->resize(dim());
  return costFunction()->Evaluate(params.data(), residual->data(), nullptr);
}

double Factor::error(const Values& values) const {
  Eigen::VectorXd r;
  if (!whitenedError(values, &r)) return std::numeric_limits<double>::infinity();
  return 0.5 * r.squaredNorm();
}

bool Factor::linearize(const Values& values, Linearization* out) const {
  using RowMatX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const std::size_t n = keys_.size();
  std::vector<const double*> params(n);
  std::vector<RowMatX> ambient(n);
  std::vector<double*> jac_ptrs(n);
  for (std::size_t i = 0; i < n; ++i) {
    params[i] = values.data(keys_[i]);
    ambient[i].resize(dim(), values.ambientDim(keys_[i]));
    jac_ptrs[i] = ambient[i].data();
  }
  out->residual.resize(dim());
  if (!costFunction()->Evaluate(params.data(), out->residual.data(), jac_ptrs.data())) return false;
  out->jacobians.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const ceres::Manifold* m = values.manifold(keys_[i]);
    if (!m) {
      out->jacobians[i] = ambient[i];
      continue;
    }
    RowMatX plus(m->AmbientSize(), m->TangentSize());
    m->PlusJacobian(params[i], plus.data());
    out->jacobians[i] = ambient[i] * plus;
  }
  return true;
}

bool Factor::evaluateTangent(const double* const* x, const ceres::Manifold* const* manifolds,
                             double* residual, double** tangent_jacobians) const {
  using RowMatX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const ceres::CostFunction& cost = *costFunction();
  const std::size_t n = keys_.size();
  if (!tangent_jacobians) return cost.Evaluate(x, residual, nullptr);
  std::vector<RowMatX> ambient(n);
  std::vector<double*> ptrs(n, nullptr);
  for (std::size_t i = 0; i < n; ++i) {
    if (!tangent_jacobians[i]) continue;
    ambient[i].resize(dim(), cost.parameter_block_sizes()[i]);
    ptrs[i] = ambient[i].data();
  }
  if (!cost.Evaluate(x, residual, ptrs.data())) return false;
  for (std::size_t i = 0; i < n; ++i) {
    if (!tangent_jacobians[i]) continue;
    const ceres::Manifold* m = manifolds[i];
    const int t = m ? m->TangentSize() : static_cast<int>(ambient[i].cols());
    Eigen::Map<RowMatX> out(tangent_jacobians[i], dim(), t);
    if (!m) {
      out = ambient[i];
      continue;
    }
    RowMatX plus(m->AmbientSize(), t);
    m->PlusJacobian(x[i], plus.data());
    out.noalias() = ambient[i] * plus;
  }
  return true;
}

}  // namespace hdvio
