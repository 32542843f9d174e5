#pragma once
// Marginalization by Schur complement. The factors touching the removed variables are
// linearized at the current values; the removed block is eliminated from the Gauss-Newton
// system; the result is factored back into an ordinary MarginalizationPrior on the remaining
// variables (the removed variables' Markov blanket). Inverses are symmetric
// eigen-decompositions with thresholds, so rank-deficient blocks (gauge freedoms, landmarks
// seen once) are handled instead of crashing.
#include <memory>
#include <set>

#include "hdvio/backend/marginalization_prior.h"
#include "hdvio/core/factor_graph.h"

namespace hdvio {

struct MarginalizationOptions {
  // Eigenvalues of the Jacobi-scaled (unit-diagonal) information below this are treated as
  // zero: directions with less than this fraction of their variables' own information.
  double eigen_threshold = 1e-9;
};

// Returns nullptr if no variable remains connected (the information simply leaves the window).
std::shared_ptr<MarginalizationPrior> marginalizeBySchurComplement(
    const FactorGraph& factors, const Values& values, const std::set<Key>& marginalized,
    const MarginalizationOptions& options = {});

// The dense Gauss-Newton system H dx = -b of a graph over keys (in that order), whitened and
// robustified like Ceres does to first order. Exposed for tests and diagnostics.
struct LinearSystem {
  std::vector<Key> keys;
  std::vector<int> offsets;
  Eigen::MatrixXd H;
  Eigen::VectorXd b;
};
LinearSystem linearizeDense(const FactorGraph& factors, const Values& values,
                            const std::vector<Key>& keys);

}  // namespace hdvio
