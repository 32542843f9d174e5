#pragma once
// Levenberg-Marquardt on a FactorGraph without Ceres: the variables whose key letter is in
// options.eliminate_first (the landmarks of a window) are eliminated by a Schur complement per
// variable, the rest is solved as one system by a block-sparse Cholesky. Same damping and
// trust-region rules as Ceres' LEVENBERG_MARQUARDT with DENSE_SCHUR, so it is a drop-in for that
// solver (OptimizerOptions::optimizer = kSchurLm), plus one way to stop Ceres lacks: after a step
// that lowered the cost by what the quadratic model predicted, to within function_tolerance (the
// next step could only lower it by about that mismatch). What it saves is Ceres' per-solve problem
// build and preprocessing, its ambient-space Jacobians (factors give tangent Jacobians
// directly), the dense Cholesky of the reduced system and, for a factor with a constant Jacobian
// (Factor::constantJacobian, the marginalization prior), its evaluation and J^T J product in
// every iteration. options.max_time_s and linear_solver are not used: nothing in a solve
// depends on the clock.
#include "hdvio/core/ceres_bridge.h"

namespace hdvio {

// Optimizes values in place (left as they were when the result is not usable). Fills the parts
// of result.summary the project reads: iterations (with trust_region_radius), initial and final
// cost, termination type and message, residual / parameter block counts, linear solves, total
// time.
// Throws std::logic_error if a factor connects two eliminated variables.
OptimizeResult optimizeSchurLm(const FactorGraph& graph, Values* values, const OptimizerOptions& options);

}  // namespace hdvio
