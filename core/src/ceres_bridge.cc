#include "hdvio/core/ceres_bridge.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

#include <ceres/ordered_groups.h>

namespace hdvio {

ceres::Problem::Options problemOptions() {
  ceres::Problem::Options o;
  o.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  o.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return o;
}

namespace {

// Ceres keeps the blocks of an elimination group in a std::set<double*>, i.e. in address
// order, and eliminates them in that order. Heap addresses change from run to run (and between
// builds), and so would every rounding downstream. Solving on a copy of the variables laid out
// in one buffer in key order makes the order, and the result, a function of the keys alone.
class KeyOrderedBlocks {
 public:
  explicit KeyOrderedBlocks(const Values& values) {
    std::size_t size = 0;
    for (Key k : values.keys()) {
      offset_[k] = size;
      size += static_cast<std::size_t>(values.ambientDim(k));
    }
    buffer_.resize(size);
    for (const auto& [k, offset] : offset_)
      std::copy_n(values.data(k), values.ambientDim(k), buffer_.data() + offset);
  }
  double* data(Key k) { return buffer_.data() + offset_.at(k); }
  void copyTo(Values* values) const {
    for (const auto& [k, offset] : offset_)
      std::copy_n(buffer_.data() + offset, values->ambientDim(k), values->data(k));
  }

 private:
  std::map<Key, std::size_t> offset_;
  std::vector<double> buffer_;
};

template <typename BlockOf>
void addFactors(const FactorGraph& graph, const Values& values, const std::set<Key>& constant_keys,
                BlockOf&& block_of, ceres::Problem* problem) {
  std::set<Key> added;
  for (const auto& factor : graph) {
    std::vector<double*> blocks;
    for (Key k : factor->keys()) {
      if (!values.exists(k))
        throw std::logic_error("addToProblem: factor refers to missing variable " + k.str());
      double* block = block_of(k);
      if (added.insert(k).second) {
        problem->AddParameterBlock(block, values.ambientDim(k), values.manifold(k));
        if (constant_keys.count(k)) problem->SetParameterBlockConstant(block);
      }
      blocks.push_back(block);
    }
    problem->AddResidualBlock(factor->costFunction(), factor->loss(), blocks);
  }
}

// Two elimination groups: the variables named by eliminate_first (unless held constant),
// then the rest. Null when nothing would be eliminated first, so Ceres chooses as before.
std::shared_ptr<ceres::ParameterBlockOrdering> eliminationOrdering(
    const OptimizerOptions& options, const Values& values, KeyOrderedBlocks* blocks,
    const ceres::Problem& problem) {
  const ceres::LinearSolverType s = options.linear_solver;
  const bool schur = s == ceres::DENSE_SCHUR || s == ceres::SPARSE_SCHUR || s == ceres::ITERATIVE_SCHUR;
  if (!schur || options.eliminate_first.empty()) return nullptr;
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  int first = 0;
  for (Key k : values.keys()) {
    double* block = blocks->data(k);
    if (!problem.HasParameterBlock(block)) continue;
    const bool eliminate =
        options.eliminate_first.count(k.letter()) > 0 && !problem.IsParameterBlockConstant(block);
    ordering->AddElementToGroup(block, eliminate ? 0 : 1);
    first += eliminate ? 1 : 0;
  }
  return first > 0 ? ordering : nullptr;
}

}  // namespace

void addToProblem(const FactorGraph& graph, Values* values, const std::set<Key>& constant_keys,
                  ceres::Problem* problem) {
  addFactors(graph, *values, constant_keys, [values](Key k) { return values->data(k); }, problem);
}

OptimizeResult optimize(const FactorGraph& graph, Values* values,
                        const OptimizerOptions& options) {
  ceres::Problem problem(problemOptions());
  KeyOrderedBlocks blocks(*values);
  addFactors(graph, *values, options.constant_keys, [&blocks](Key k) { return blocks.data(k); },
             &problem);
  ceres::Solver::Options solver;
  solver.max_num_iterations = options.max_iterations;
  solver.max_solver_time_in_seconds = options.max_time_s;
  solver.num_threads = options.threads;
  solver.linear_solver_type = options.linear_solver;
  solver.function_tolerance = options.function_tolerance;
  solver.initial_trust_region_radius = options.initial_trust_region_radius;
  solver.linear_solver_ordering = eliminationOrdering(options, *values, &blocks, problem);
  solver.minimizer_progress_to_stdout = options.verbose;
  solver.logging_type = options.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  OptimizeResult result;
  ceres::Solve(solver, &problem, &result.summary);
  blocks.copyTo(values);
  if (options.verbose) std::printf("%s\n", result.summary.FullReport().c_str());
  result.usable = result.summary.termination_type != ceres::FAILURE &&
                  std::isfinite(result.summary.final_cost);
  return result;
}

}  // namespace hdvio
