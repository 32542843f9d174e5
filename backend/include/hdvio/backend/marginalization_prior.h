#pragma once
// The factor a marginalization leaves behind: a Gaussian prior on the variables that were
// connected to the removed ones, kept at its own linearization point x0:
//     r(x) = r0 + J0 * (x (-) x0)        (already whitened; tangent-space J0)
// J0 stays fixed (first-estimate Jacobians) so the prior adds no information along directions
// that were unobservable at x0, which keeps the sliding window consistent.
#include <memory>
#include <vector>

#include <ceres/cost_function.h>

#include "hdvio/core/factor.h"
#include "hdvio/core/values.h"

namespace hdvio {

class MarginalizationPrior : public Factor {
 public:
  // keys: the remaining variables, in the column order of J0; x0 holds their linearization point.
  MarginalizationPrior(const std::vector<Key>& keys, const Values& x0, Eigen::MatrixXd J0,
                       Eigen::VectorXd r0);

  ceres::CostFunction* costFunction() const override { return cost_.get(); }
  const Eigen::MatrixXd& jacobian() const { return J0_; }
  // The tangent Jacobian is J0 at every point: r = r0 + J0 (x - x0), the difference in the
  // manifolds' tangent spaces (Ceres' MinusJacobian x PlusJacobian is the identity).
  ConstantJacobian constantJacobian() const override { return {&J0_, &information_}; }
  const Eigen::VectorXd& residualAtLinearizationPoint() const { return r0_; }
  const Values& linearizationPoint() const { return x0_; }
  // The same prior about another linearization point (a change of gauge moves it with the
  // window, so the prior keeps saying what it said).
  std::shared_ptr<MarginalizationPrior> withLinearizationPoint(const Values& x0) const {
    return std::make_shared<MarginalizationPrior>(keys(), x0, J0_, r0_);
  }

 private:
  class Cost;
  Values x0_;  // only the prior's own variables
  std::vector<int> offsets_;  // tangent column offset of each key in J0
  Eigen::MatrixXd J0_;
  Eigen::VectorXd r0_;
  Eigen::MatrixXd information_;  // J0^T J0
  std::unique_ptr<ceres::CostFunction> cost_;
};

}  // namespace hdvio
