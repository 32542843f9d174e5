#include "hdvio/core/ceres_bridge.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <stdexcept>
#include <vector>

#include <ceres/ordered_groups.h>

#include "hdvio/core/schur_lm.h"

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
// The blocks are a vector sorted by key: one binary search per factor key while the problem is
// built (a window has ~1100 factors).
class KeyOrderedBlocks {
 public:
  struct Block {
    Key key;
    std::size_t offset = 0;
    int dim = 0;
    ceres::Manifold* manifold = nullptr;
    bool added = false;  // already a parameter block of the problem
  };

  explicit KeyOrderedBlocks(const Values& values) {
    const std::vector<Key> keys = values.keys();  // sorted
    blocks_.reserve(keys.size());
    std::size_t size = 0;
    for (Key k : keys) {
      Block b;
      b.key = k;
      b.offset = size;
      b.dim = values.ambientDim(k);
      b.manifold = values.manifold(k);
      blocks_.push_back(b);
      size += static_cast<std::size_t>(b.dim);
    }
    buffer_.resize(size);
    for (const Block& b : blocks_) std::copy_n(values.data(b.key), b.dim, buffer_.data() + b.offset);
  }
  Block* find(Key k) {
    auto it = std::lower_bound(blocks_.begin(), blocks_.end(), k,
                               [](const Block& b, Key key) { return b.key < key; });
    return it != blocks_.end() && it->key.value() == k.value() ? &*it : nullptr;
  }
  double* data(const Block& b) { return buffer_.data() + b.offset; }
  const std::vector<Block>& blocks() const { return blocks_; }
  void copyTo(Values* values) const {
    for (const Block& b : blocks_) std::copy_n(buffer_.data() + b.offset, b.dim, values->data(b.key));
  }

 private:
  std::vector<Block> blocks_;
  std::vector<double> buffer_;
};

// Same calls in the same order as addFactors below (so the same problem), on the buffer.
void addFactorsOnBlocks(const FactorGraph& graph, const std::set<Key>& constant_keys,
                        KeyOrderedBlocks* kb, ceres::Problem* problem) {
  std::vector<double*> blocks;
  for (const auto& factor : graph) {
    blocks.clear();
    const std::vector<int32_t>& sizes = factor->costFunction()->parameter_block_sizes();
    const std::vector<Key>& keys = factor->keys();
    for (std::size_t i = 0; i < keys.size(); ++i) {
      const Key k = keys[i];
      KeyOrderedBlocks::Block* b = kb->find(k);
      if (!b) throw std::logic_error("addToProblem: factor refers to missing variable " + k.str());
      // What Ceres' safety checks (off below) would catch: a size mismatch, a repeated key.
      if (i >= sizes.size() || sizes[i] != b->dim)
        throw std::logic_error("addToProblem: block size of " + k.str() + " does not match its factor");
      for (std::size_t j = 0; j < i; ++j)
        if (keys[j].value() == k.value())
          throw std::logic_error("addToProblem: a factor lists " + k.str() + " twice");
      double* block = kb->data(*b);
      if (!b->added) {
        b->added = true;
        problem->AddParameterBlock(block, b->dim, b->manifold);
        if (constant_keys.count(k)) problem->SetParameterBlockConstant(block);
      }
      blocks.push_back(block);
    }
    problem->AddResidualBlock(factor->costFunction(), factor->loss(), blocks);
  }
}

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
    const OptimizerOptions& options, KeyOrderedBlocks* blocks, const ceres::Problem& problem) {
  const ceres::LinearSolverType s = options.linear_solver;
  const bool schur = s == ceres::DENSE_SCHUR || s == ceres::SPARSE_SCHUR || s == ceres::ITERATIVE_SCHUR;
  if (!schur || options.eliminate_first.empty()) return nullptr;
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  int first = 0;
  for (const KeyOrderedBlocks::Block& b : blocks->blocks()) {
    if (!b.added) continue;  // no factor uses it
    double* block = blocks->data(b);
    const bool eliminate =
        options.eliminate_first.count(b.key.letter()) > 0 && !problem.IsParameterBlockConstant(block);
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
  if (options.optimizer == OptimizerOptions::Optimizer::kSchurLm)
    return optimizeSchurLm(graph, values, options);
  ceres::Problem::Options problem_options = problemOptions();
  problem_options.disable_all_safety_checks = true;  // addFactorsOnBlocks checks what they would
  ceres::Problem problem(problem_options);
  KeyOrderedBlocks blocks(*values);
  addFactorsOnBlocks(graph, options.constant_keys, &blocks, &problem);
  ceres::Solver::Options solver;
  solver.max_num_iterations = options.max_iterations;
  solver.max_solver_time_in_seconds = options.max_time_s;
  solver.num_threads = options.threads;
  solver.linear_solver_type = options.linear_solver;
  solver.function_tolerance = options.function_tolerance;
  solver.initial_trust_region_radius = options.initial_trust_region_radius;
  solver.linear_solver_ordering = eliminationOrdering(options, &blocks, problem);
  solver.minimizer_progress_to_stdout = options.verbose;
  solver.logging_type = options.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  OptimizeResult result;
  ceres::Solve(solver, &problem, &result.summary);
  if (options.verbose) std::printf("%s\n", result.summary.FullReport().c_str());
  result.usable = result.summary.termination_type != ceres::FAILURE &&
                  std::isfinite(result.summary.final_cost);
  if (result.usable) blocks.copyTo(values);
  return result;
}

}  // namespace hdvio
