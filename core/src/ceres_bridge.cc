#include "hdvio/core/ceres_bridge.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include <ceres/ordered_groups.h>

namespace hdvio {

ceres::Problem::Options problemOptions() {
  ceres::Problem::Options o;
  o.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return o;
}

void addToProblem(const FactorGraph& graph, Values* values, const std::set<Key>& constant_keys,
                  ceres::Problem* problem) {
  std::set<Key> added;
  for (const auto& factor : graph) {
    std::vector<double*> blocks;
    for (Key k : factor->keys()) {
      if (!values->exists(k))
        throw std::logic_error("addToProblem: factor refers to missing variable " + k.str());
      double* block = values->data(k);
      if (added.insert(k).second) {
        problem->AddParameterBlock(block, values->ambientDim(k), values->manifold(k));
        if (constant_keys.count(k)) problem->SetParameterBlockConstant(block);
      }
      blocks.push_back(block);
    }
    problem->AddResidualBlock(factor->costFunction(), factor->loss(), blocks);
  }
}

namespace {

// Two elimination groups: the variables named by eliminate_first (unless held constant),
// then the rest. Null when nothing would be eliminated first, so Ceres chooses as before.
std::shared_ptr<ceres::ParameterBlockOrdering> eliminationOrdering(
    const OptimizerOptions& options, Values* values, const ceres::Problem& problem) {
  const ceres::LinearSolverType s = options.linear_solver;
  const bool schur = s == ceres::DENSE_SCHUR || s == ceres::SPARSE_SCHUR || s == ceres::ITERATIVE_SCHUR;
  if (!schur || options.eliminate_first.empty()) return nullptr;
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  int first = 0;
  for (Key k : values->keys()) {
    double* block = values->data(k);
    if (!problem.HasParameterBlock(block)) continue;
    const bool eliminate =
        options.eliminate_first.count(k.letter()) > 0 && !problem.IsParameterBlockConstant(block);
    ordering->AddElementToGroup(block, eliminate ? 0 : 1);
    first += eliminate ? 1 : 0;
  }
  return first > 0 ? ordering : nullptr;
}

}  // namespace

OptimizeResult optimize(const FactorGraph& graph, Values* values,
                        const OptimizerOptions& options) {
  ceres::Problem problem(problemOptions());
  addToProblem(graph, values, options.constant_keys, &problem);
  ceres::Solver::Options solver;
  solver.max_num_iterations = options.max_iterations;
  solver.max_solver_time_in_seconds = options.max_time_s;
  solver.num_threads = options.threads;
  solver.linear_solver_type = options.linear_solver;
  solver.function_tolerance = options.function_tolerance;
  solver.initial_trust_region_radius = options.initial_trust_region_radius;
  solver.linear_solver_ordering = eliminationOrdering(options, values, problem);
  solver.minimizer_progress_to_stdout = options.verbose;
  solver.logging_type = options.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  OptimizeResult result;
  ceres::Solve(solver, &problem, &result.summary);
  if (options.verbose) std::printf("%s\n", result.summary.FullReport().c_str());
  result.usable = result.summary.termination_type != ceres::FAILURE &&
                  std::isfinite(result.summary.final_cost);
  return result;
}

}  // namespace hdvio
