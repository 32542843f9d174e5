#pragma once
// The one place where a FactorGraph and Values become a ceres::Problem and get optimized.
#include <set>

#include <ceres/problem.h>
#include <ceres/solver.h>

#include "hdvio/core/factor_graph.h"
#include "hdvio/core/values.h"

namespace hdvio {

struct OptimizerOptions {
  int max_iterations = 50;
  double max_time_s = 1e6;
  int threads = 1;
  bool verbose = false;
  ceres::LinearSolverType linear_solver = ceres::SPARSE_NORMAL_CHOLESKY;
  std::set<Key> constant_keys;  // held fixed (gauge, or variables outside the window)
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

// Optimizes values in place.
OptimizeResult optimize(const FactorGraph& graph, Values* values, const OptimizerOptions& options);

}  // namespace hdvio
