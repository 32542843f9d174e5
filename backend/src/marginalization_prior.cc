#include "hdvio/backend/marginalization_prior.h"

#include <stdexcept>

namespace hdvio {

class MarginalizationPrior::Cost : public ceres::CostFunction {
 public:
  explicit Cost(const MarginalizationPrior* prior) : prior_(prior) {
    set_num_residuals(static_cast<int>(prior->r0_.size()));
    for (Key k : prior->keys()) mutable_parameter_block_sizes()->push_back(prior->x0_.ambientDim(k));
  }

  bool Evaluate(double const* const* x, double* residual, double** jacobians) const override {
    using RowMatX = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const auto& keys = prior_->keys();
    const Values& x0 = prior_->x0_;
    Eigen::VectorXd dx(prior_->J0_.cols());
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const Key k = keys[i];
      const int n = x0.tangentDim(k);
      const ceres::Manifold* m = x0.manifold(k);
      if (m) {
        if (!m->Minus(x[i], x0.data(k), dx.data() + prior_->offsets_[i])) return false;
      } else {
        for (int c = 0; c < n; ++c) dx[prior_->offsets_[i] + c] = x[i][c] - x0.data(k)[c];
      }
    }
    Eigen::Map<Eigen::VectorXd>(residual, num_residuals()) = prior_->r0_ + prior_->J0_ * dx;
    if (!jacobians) return true;
    for (std::size_t i = 0; i < keys.size(); ++i) {
      if (!jacobians[i]) continue;
      const Key k = keys[i];
      const int n = x0.tangentDim(k);
      const int a = x0.ambientDim(k);
      Eigen::Map<RowMatX> J(jacobians[i], num_residuals(), a);
      const auto Jt = prior_->J0_.middleCols(prior_->offsets_[i], n);
      const ceres::Manifold* m = x0.manifold(k);
      if (!m) {
        J = Jt;
      } else {
        // Lift the fixed tangent Jacobian to ambient coordinates at the current x.
        RowMatX lift(n, a);
        m->MinusJacobian(x[i], lift.data());
        J = Jt * lift;
      }
    }
    return true;
  }

 private:
  const MarginalizationPrior* prior_;
};

MarginalizationPrior::MarginalizationPrior(const std::vector<Key>& keys, const Values& x0,
                                           Eigen::MatrixXd J0, Eigen::VectorXd r0)
    : Factor(keys, NoiseModel::isotropic(static_cast<int>(r0.size()), 1.0)),
      J0_(std::move(J0)),
      r0_(std::move(r0)) {
  x0_ = x0.subset(keys);
  int offset = 0;
  for (Key k : keys) {
    offsets_.push_back(offset);
    offset += x0.tangentDim(k);
  }
  if (offset != J0_.cols() || J0_.rows() != r0_.size())
    throw std::invalid_argument("MarginalizationPrior: J0 does not match the keys' tangent sizes");
  information_.noalias() = J0_.transpose() * J0_;
  cost_ = std::make_unique<Cost>(this);
}

}  // namespace hdvio
