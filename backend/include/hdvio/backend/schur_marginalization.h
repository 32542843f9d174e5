#pragma once
// Marginalization by Schur complement. The factors touching the removed variables are
// linearized at the current values; the removed block is eliminated from the Gauss-Newton
// system; the result is factored back into an ordinary MarginalizationPrior on the remaining
// variables (the removed variables' Markov blanket). Landmarks are eliminated one by one
// first (options below), then the rest densely. Inverses are thresholded symmetric
// eigen-decompositions and the final factorization a Cholesky with full diagonal pivoting
// that stops at the threshold, so rank-deficient blocks (gauge freedoms, landmarks seen once)
// are handled instead of crashing.
#include <memory>
#include <set>

#include "hdvio/backend/marginalization_prior.h"
#include "hdvio/core/factor_graph.h"

namespace hdvio {

struct MarginalizationOptions {
  // Eigenvalues (and final pivots) of the Jacobi-scaled (unit-diagonal) information below this
  // are treated as zero: directions with less than this fraction of their variables' own
  // information.
  double eigen_threshold = 1e-9;
  // Removed variables of at most 3 dimensions that share no factor with each other (the
  // landmarks leaving with a keyframe) are eliminated one at a time, each a small Schur
  // complement onto the poses observing it, before the dense elimination of the rest. The cost
  // then grows linearly with the number of landmarks instead of cubically. false: one dense
  // elimination of everything (the reference in tests).
  bool eliminate_independent_first = true;
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
