#pragma once
// Central-difference Jacobians of a factor's whitened residual with respect to the tangent
// space of each of its variables, for checking analytic Jacobians (Factor::linearize).
#include <vector>

#include <Eigen/Core>

#include "hdvio/core/factor.h"
#include "hdvio/core/values.h"

namespace hdvio {

std::vector<Eigen::MatrixXd> numericalJacobians(const Factor& factor, const Values& values,
                                                double step = 1e-6);

// Largest |analytic - numeric| over all entries, relative to max(1, |numeric|_max).
double maxJacobianError(const Factor& factor, const Values& values, double step = 1e-6);

}  // namespace hdvio
