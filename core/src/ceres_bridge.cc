#include "hdvio/core/ceres_bridge.h"

#include <cmath>
#include <stdexcept>

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

OptimizeResult optimize(const FactorGraph& graph, Values* values,
                        const OptimizerOptions& options) {
  ceres::Problem problem(problemOptions());
  addToProblem(graph, values, options.constant_keys, &problem);
  ceres::Solver::Options solver;
  solver.max_num_iterations = options.max_iterations;
  solver.max_solver_time_in_seconds = options.max_time_s;
  solver.num_threads = options.threads;
  solver.linear_solver_type = options.linear_solver;
  solver.minimizer_progress_to_stdout = options.verbose;
  solver.logging_type = options.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  OptimizeResult result;
  ceres::Solve(solver, &problem, &result.summary);
  result.usable = result.summary.termination_type != ceres::FAILURE &&
                  std::isfinite(result.summary.final_cost);
  return result;
}

}  // namespace hdvio
