#include "hdvio/core/numerical_jacobian.h"

#include <algorithm>
#include <stdexcept>

namespace hdvio {

std::vector<Eigen::MatrixXd> numericalJacobians(const Factor& factor, const Values& values,
                                                double step) {
  std::vector<Eigen::MatrixXd> out;
  for (Key key : factor.keys()) {
    const int n = values.tangentDim(key);
    Eigen::MatrixXd J(factor.dim(), n);
    for (int c = 0; c < n; ++c) {
      Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
      d[c] = step;
      Values plus = values, minus = values;
      plus.update(key, values.plus(key, d));
      minus.update(key, values.plus(key, -d));
      Eigen::VectorXd rp, rm;
      if (!factor.whitenedError(plus, &rp) || !factor.whitenedError(minus, &rm))
        throw std::runtime_error("numericalJacobians: factor evaluation failed");
      J.col(c) = (rp - rm) / (2.0 * step);
    }
    out.push_back(J);
  }
  return out;
}

double maxJacobianError(const Factor& factor, const Values& values, double step) {
  Linearization lin;
  if (!factor.linearize(values, &lin)) throw std::runtime_error("maxJacobianError: linearize failed");
  const auto numeric = numericalJacobians(factor, values, step);
  double worst = 0.0;
  for (std::size_t i = 0; i < numeric.size(); ++i) {
    const double scale = std::max(1.0, numeric[i].cwiseAbs().maxCoeff());
    worst = std::max(worst, (lin.jacobians[i] - numeric[i]).cwiseAbs().maxCoeff() / scale);
  }
  return worst;
}

}  // namespace hdvio
