#pragma once
// The one place where a FactorGraph and Values become a ceres::Problem and get optimized.
#include <set>

#include <ceres/problem.h>
#include <ceres/solver.h>

#include "hdvio/core/factor_graph.h"
#include "hdvio/core/values.h"

namespace hdvio {

struct OptimizerOptions {
  // kCeres: ceres::Solve. kSchurLm: hdvio's own Levenberg-Marquardt with the eliminate_first
  // variables Schur-complemented out (schur_lm.h); linear_solver is then not used.
  enum class Optimizer { kCeres, kSchurLm };
  Optimizer optimizer = Optimizer::kCeres;
  int max_iterations = 50;
  double max_time_s = 1e6;
  int threads = 1;
  bool verbose = false;
  ceres::LinearSolverType linear_solver = ceres::SPARSE_NORMAL_CHOLESKY;
  std::set<Key> constant_keys;  // held fixed (gauge, or variables outside the window)
  // Ceres stops when an iteration lowers the cost by less than this fraction.
  double function_tolerance = 1e-6;
  // Levenberg-Marquardt starts with damping 1/radius (relative to the Jacobi-scaled diagonal).
  // Ceres' 1e4 suits a poor start; from a good one a large radius (nearly Gauss-Newton) takes
  // far fewer iterations, and LM still rejects bad steps and shrinks the radius.
  double initial_trust_region_radius = 1e4;
  // Schur solvers: variables whose key letter is listed are eliminated first (e.g. {'l'}, the
  // landmarks). Without it Ceres picks its own independent set, which may mix in velocities
  // and biases and so force its slow dynamic-size Schur eliminator.
  std::set<char> eliminate_first;
};

struct OptimizeResult {
  ceres::Solver::Summary summary;
  bool usable = false;  // Ceres reported CONVERGENCE or NO_CONVERGENCE with a finite cost
};

// Adds every factor of graph over the variables of values (all keys must exist) to problem.
// The problem must have been created with problemOptions() so ownership stays with hdvio.
void addToProblem(const FactorGraph& graph, Values* values, const std::set<Key>& constant_keys,
                  ceres::Problem* problem);
ceres::Problem::Options problemOptions();

// Optimizes values in place; when the solve is not usable they are left as they were (verbose:
// prints Ceres' full report too).
OptimizeResult optimize(const FactorGraph& graph, Values* values, const OptimizerOptions& options);

}  // namespace hdvio
