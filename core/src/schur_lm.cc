#include "hdvio/core/schur_lm.h"

#include "hdvio/core/block_sparse_cholesky.h"
#include "schur_lm_blocks.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <ceres/loss_function.h>

namespace hdvio {
namespace {

using schur_lm_blocks::addJtJ;
using schur_lm_blocks::addTwoRowProduct;
using schur_lm_blocks::applyLoss;
using schur_lm_blocks::ConstRowMap;
using schur_lm_blocks::ConstVecMap;
using schur_lm_blocks::RowMap;
using schur_lm_blocks::setJtJ;
using schur_lm_blocks::landmarkColumns;
using schur_lm_blocks::landmarkV;
using schur_lm_blocks::subtractColumns3;
using schur_lm_blocks::subtractLandmarkWtd;
using schur_lm_blocks::subtractProduct;

// Ceres' defaults for LEVENBERG_MARQUARDT (solver.h, levenberg_marquardt_strategy.cc).
constexpr double kMinDiagonal = 1e-6, kMaxDiagonal = 1e32;
constexpr double kMaxRadius = 1e16, kMinRadius = 1e-32;
constexpr double kMinRelativeDecrease = 1e-3;
constexpr double kParameterTolerance = 1e-8, kGradientTolerance = 1e-10;
constexpr int kMaxConsecutiveInvalidSteps = 5;

enum class Role { kUnused, kConstant, kReduced, kEliminated };

struct Variable {
  Key key;
  const ceres::Manifold* manifold = nullptr;
  int ambient = 0, tangent = 0;
  std::size_t x_offset = 0;  // in the parameter buffer
  Role role = Role::kUnused;
  int dx_offset = -1;        // in the step: reduced variables first, then the eliminated ones
  int eliminated = -1;       // index in SchurLm::elim_ (kEliminated)
};

struct Slot {  // one factor and where its residual and Jacobians live
  const Factor* factor = nullptr;
  // Per key: the variable, where its Jacobian lives (row-major dim x tangent; non-constant keys)
  // and its J_key^T J_e (reduced keys of a slot with an eliminated one). One array per slot.
  struct KeyRef {
    int var = 0;
    std::size_t j_offset = 0, w_offset = 0;
  };
  std::vector<KeyRef> keys;
  int dim = 0;
  std::size_t r_offset = 0;
  int eliminated_pos = -1;            // position of the eliminated key, -1 none
  // A factor with a constant Jacobian (Factor::constantJacobian): its J, J^T J and the column
  // of each key in them; its Jacobians are then neither evaluated nor stored.
  Factor::ConstantJacobian constant;
  std::vector<int> constant_col;
};

struct EliminatedBlock {
  int var = 0;
  std::vector<std::pair<int, int>> uses;  // (slot, position of a reduced key in it)
  Eigen::MatrixXd H, A_inv;               // J_e^T J_e and (H + damping)^-1
  Eigen::VectorXd g;                      // J_e^T r
};

class SchurLm {
 public:
  SchurLm(const FactorGraph& graph, const Values& values, const OptimizerOptions& options);
  OptimizeResult run();
  void copyTo(Values* values) const;

 private:
  bool evaluate(const std::vector<double>& x, bool jacobians, double* cost);
  void buildNormalEquations();
  void addDenseSlot(const Slot& slot);
  void addConstantSlot(const Slot& slot);
  bool solveStep(double radius);
  double modelCostChange();
  void stepFrom(const std::vector<double>& x, std::vector<double>* out) const;

  const OptimizerOptions& options_;
  std::vector<Variable> vars_;
  std::vector<Slot> slots_;
  std::vector<EliminatedBlock> elim_;
  std::vector<double> x_, candidate_, r_, r_trial_, J_, W_, V_;  // V = W (H_e + damping)^-1, as W
  int num_reduced_ = 0, num_step_ = 0;
  Eigen::MatrixXd H_rr_, S_, dense_J_, dense_G_;
  std::vector<int> block_offsets_, block_sizes_;  // the reduced variables in the step
  BlockSparseCholesky cholesky_;
  Eigen::VectorXd g_r_, diagonal_, dx_;
  Eigen::VectorXd jd_;  // J dx of one factor (modelCostChange), sized for the largest
  // One eliminated variable's uses in solveStep: where each reduced variable sits, its W and V.
  struct UseRef {
    int dx_offset, tangent;
    const double *W, *V;
  };
  std::vector<UseRef> uses_;
};

SchurLm::SchurLm(const FactorGraph& graph, const Values& values, const OptimizerOptions& options)
    : options_(options) {
  const std::vector<Key> keys = values.keys();  // sorted: the step's layout follows the keys
  vars_.resize(keys.size());
  std::size_t x_size = 0;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    Variable& v = vars_[i];
    v.key = keys[i];
    v.manifold = values.manifold(keys[i]);
    v.ambient = values.ambientDim(keys[i]);
    v.tangent = values.tangentDim(keys[i]);
    v.x_offset = x_size;
    x_size += static_cast<std::size_t>(v.ambient);
  }
  x_.resize(x_size);
  for (const Variable& v : vars_) std::copy_n(values.data(v.key), v.ambient, x_.data() + v.x_offset);
  auto find = [&](Key k) {
    auto it = std::lower_bound(keys.begin(), keys.end(), k);
    if (it == keys.end() || it->value() != k.value())
      throw std::logic_error("optimizeSchurLm: factor refers to missing variable " + k.str());
    return static_cast<int>(it - keys.begin());
  };
  slots_.resize(graph.size());
  std::size_t r_size = 0;
  for (std::size_t s = 0; s < graph.size(); ++s) {
    Slot& slot = slots_[s];
    slot.factor = graph[s].get();
    slot.dim = slot.factor->dim();
    slot.r_offset = r_size;
    r_size += static_cast<std::size_t>(slot.dim);
    slot.keys.reserve(slot.factor->keys().size());
    for (Key k : slot.factor->keys()) {
      const int i = find(k);
      Variable& v = vars_[i];
      if (v.role == Role::kUnused) {
        v.role = options.constant_keys.count(k)                ? Role::kConstant
                 : options.eliminate_first.count(k.letter()) ? Role::kEliminated
                                                               : Role::kReduced;
      }
      slot.keys.push_back({i});
    }
    slot.constant = slot.factor->constantJacobian();
  }
  r_.resize(r_size);
  r_trial_.resize(r_size);
  int max_dim = 0;
  for (const Slot& slot : slots_) max_dim = std::max(max_dim, slot.dim);
  jd_.resize(max_dim);
  // Step layout: reduced variables (key order), then the eliminated ones (key order).
  for (Variable& v : vars_)
    if (v.role == Role::kReduced) {
      v.dx_offset = num_step_;
      block_offsets_.push_back(num_step_);
      block_sizes_.push_back(v.tangent);
      num_step_ += v.tangent;
    }
  num_reduced_ = num_step_;
  for (std::size_t i = 0; i < vars_.size(); ++i) {
    Variable& v = vars_[i];
    if (v.role != Role::kEliminated) continue;
    v.dx_offset = num_step_;
    num_step_ += v.tangent;
    v.eliminated = static_cast<int>(elim_.size());
    EliminatedBlock b;
    b.var = static_cast<int>(i);
    b.H.resize(v.tangent, v.tangent);
    b.A_inv.resize(v.tangent, v.tangent);
    b.g.resize(v.tangent);
    elim_.push_back(std::move(b));
  }
  std::size_t j_size = 0, w_size = 0;
  for (std::size_t s = 0; s < slots_.size(); ++s) {
    Slot& slot = slots_[s];
    if (slot.constant.J) {
      int col = 0;
      bool eliminated = false;
      for (const Slot::KeyRef& k : slot.keys) {
        const int i = k.var;
        slot.constant_col.push_back(col);
        col += vars_[i].tangent;
        eliminated = eliminated || vars_[i].role == Role::kEliminated;
      }
      if (!eliminated && col == slot.constant.J->cols() && slot.dim == slot.constant.J->rows())
        continue;
      slot.constant = {};  // not the expected shape: linearize it like any other factor
      slot.constant_col.clear();
    }
    for (std::size_t p = 0; p < slot.keys.size(); ++p) {
      const Variable& v = vars_[slot.keys[p].var];
      if (v.role == Role::kConstant) continue;
      slot.keys[p].j_offset = j_size;
      j_size += static_cast<std::size_t>(slot.dim * v.tangent);
      if (v.role == Role::kEliminated) {
        if (slot.eliminated_pos >= 0)
          throw std::logic_error("optimizeSchurLm: a factor connects two eliminated variables");
        slot.eliminated_pos = static_cast<int>(p);
      }
    }
    if (slot.eliminated_pos < 0) continue;
    const Variable& e = vars_[slot.keys[slot.eliminated_pos].var];
    for (std::size_t p = 0; p < slot.keys.size(); ++p) {
      const Variable& v = vars_[slot.keys[p].var];
      if (v.role != Role::kReduced) continue;
      slot.keys[p].w_offset = w_size;
      w_size += static_cast<std::size_t>(v.tangent * e.tangent);
      elim_[e.eliminated].uses.emplace_back(static_cast<int>(s), static_cast<int>(p));
    }
  }
  J_.resize(j_size);
  W_.resize(w_size);
  V_.resize(w_size);
  H_rr_.resize(num_reduced_, num_reduced_);
  g_r_.resize(num_reduced_);
  diagonal_.resize(num_step_);
  dx_.resize(num_step_);
}

// Cost 0.5 sum rho(|r|^2) at x; with jacobians, the (loss-corrected) residuals and tangent
// Jacobians are kept for the normal equations.
bool SchurLm::evaluate(const std::vector<double>& x, bool jacobians, double* cost) {
  *cost = 0.0;
  // Sized once for the factor with the most keys; each slot fills its first n entries.
  std::size_t max_keys = 0;
  for (const Slot& slot : slots_) max_keys = std::max(max_keys, slot.keys.size());
  std::vector<const double*> params(max_keys);
  std::vector<const ceres::Manifold*> manifolds(max_keys);
  std::vector<double*> jac(max_keys);
  std::vector<int> cols(max_keys);
  for (Slot& slot : slots_) {
    const std::size_t n = slot.keys.size();
    const bool with_jacobians = jacobians && !slot.constant.J;
    for (std::size_t p = 0; p < n; ++p) {
      const Variable& v = vars_[slot.keys[p].var];
      params[p] = x.data() + v.x_offset;
      manifolds[p] = v.manifold;
      cols[p] = v.tangent;
      jac[p] = with_jacobians && v.role != Role::kConstant ? J_.data() + slot.keys[p].j_offset : nullptr;
    }
    // A cost-only evaluation (a candidate point) must not overwrite the residuals at x, which
    // the model cost change of the next step uses.
    double* r = (jacobians ? r_.data() : r_trial_.data()) + slot.r_offset;
    if (!slot.factor->evaluateTangent(params.data(), manifolds.data(), r,
                                      with_jacobians ? jac.data() : nullptr))
      return false;
    if (const ceres::LossFunction* loss = slot.factor->loss()) {
      if (slot.constant.J) throw std::logic_error("optimizeSchurLm: a constant-Jacobian factor with a loss");
      applyLoss(*loss, slot.dim, r, with_jacobians ? jac.data() : nullptr, cols.data(),
                static_cast<int>(n), cost);
    } else {
      *cost += 0.5 * ConstVecMap(r, slot.dim).squaredNorm();
    }
  }
  return std::isfinite(*cost);
}

// H_rr (upper triangle), g_r, per eliminated variable H_e, g_e and W = J_key^T J_e, and the
// damping diagonal (diag of J^T J clamped as Ceres does).
void SchurLm::buildNormalEquations() {
  H_rr_.setZero();
  g_r_.setZero();
  for (EliminatedBlock& b : elim_) {
    b.H.setZero();
    b.g.setZero();
  }
  for (const Slot& slot : slots_) {
    if (slot.constant.J) {
      addConstantSlot(slot);
      continue;
    }
    if (slot.dim > 8 && slot.eliminated_pos < 0) {  // a prior or an inertial factor: one GEMM
      addDenseSlot(slot);
      continue;
    }
    const ConstVecMap r(r_.data() + slot.r_offset, slot.dim);
    for (std::size_t a = 0; a < slot.keys.size(); ++a) {
      const Variable& va = vars_[slot.keys[a].var];
      if (va.role == Role::kConstant) continue;
      const ConstRowMap Ja(J_.data() + slot.keys[a].j_offset, slot.dim, va.tangent);
      if (va.role == Role::kEliminated) {
        EliminatedBlock& b = elim_[va.eliminated];
        addJtJ(b.H.data(), va.tangent, slot.dim, va.tangent, va.tangent, Ja.data(), Ja.data());
        b.g.noalias() += Ja.transpose().lazyProduct(r);
        continue;
      }
      g_r_.segment(va.dx_offset, va.tangent).noalias() += Ja.transpose().lazyProduct(r);
      for (std::size_t c = 0; c < slot.keys.size(); ++c) {
        const Variable& vc = vars_[slot.keys[c].var];
        if (vc.role == Role::kConstant) continue;
        const ConstRowMap Jc(J_.data() + slot.keys[c].j_offset, slot.dim, vc.tangent);
        if (vc.role == Role::kEliminated) {
          // W is row-major (ta x tc): as a column-major (tc x ta) block it is Jc^T Ja.
          setJtJ(W_.data() + slot.keys[a].w_offset, slot.dim, vc.tangent, va.tangent, Jc.data(), Ja.data());
        } else if (va.dx_offset <= vc.dx_offset) {
          addJtJ(H_rr_.data() + va.dx_offset + static_cast<std::ptrdiff_t>(vc.dx_offset) * num_reduced_,
                 num_reduced_, slot.dim, va.tangent, vc.tangent, Ja.data(), Jc.data());
        }
      }
    }
  }
  // Two keys of one factor that are the same variable add to its diagonal block twice above
  // (a, c and c, a): that is J^T J of the sum, as wanted.
  for (const Variable& v : vars_) {
    if (v.role == Role::kReduced)
      diagonal_.segment(v.dx_offset, v.tangent) = H_rr_.diagonal().segment(v.dx_offset, v.tangent);
    else if (v.role == Role::kEliminated)
      diagonal_.segment(v.dx_offset, v.tangent) = elim_[v.eliminated].H.diagonal();
  }
  diagonal_ = diagonal_.cwiseMax(kMinDiagonal).cwiseMin(kMaxDiagonal);
}

// J^T J and J^T r of a tall factor as one product of its stacked Jacobian, scattered into the
// reduced system (the marginalization prior has ~100 rows and ~15 keys: block by block the
// products would not vectorize).
void SchurLm::addDenseSlot(const Slot& slot) {
  std::vector<int> cols;
  int total = 0;
  for (std::size_t a = 0; a < slot.keys.size(); ++a) {
    cols.push_back(total);
    if (vars_[slot.keys[a].var].role == Role::kReduced) total += vars_[slot.keys[a].var].tangent;
  }
  dense_J_.resize(slot.dim, total);
  for (std::size_t a = 0; a < slot.keys.size(); ++a) {
    const Variable& v = vars_[slot.keys[a].var];
    if (v.role != Role::kReduced) continue;
    dense_J_.middleCols(cols[a], v.tangent) = ConstRowMap(J_.data() + slot.keys[a].j_offset, slot.dim, v.tangent);
  }
  dense_G_.resize(total, total);
  dense_G_.noalias() = dense_J_.transpose() * dense_J_;
  const Eigen::VectorXd gr = dense_J_.transpose() * ConstVecMap(r_.data() + slot.r_offset, slot.dim);
  for (std::size_t a = 0; a < slot.keys.size(); ++a) {
    const Variable& va = vars_[slot.keys[a].var];
    if (va.role != Role::kReduced) continue;
    g_r_.segment(va.dx_offset, va.tangent) += gr.segment(cols[a], va.tangent);
    for (std::size_t c = 0; c < slot.keys.size(); ++c) {
      const Variable& vc = vars_[slot.keys[c].var];
      if (vc.role != Role::kReduced || va.dx_offset > vc.dx_offset) continue;
      H_rr_.block(va.dx_offset, vc.dx_offset, va.tangent, vc.tangent) +=
          dense_G_.block(cols[a], cols[c], va.tangent, vc.tangent);
    }
  }
}

// A constant-Jacobian factor: its J^T J blocks as they are, J^T r by one product.
void SchurLm::addConstantSlot(const Slot& slot) {
  const Eigen::VectorXd gr =
      slot.constant.J->transpose() * ConstVecMap(r_.data() + slot.r_offset, slot.dim);
  const Eigen::MatrixXd& JtJ = *slot.constant.JtJ;
  for (std::size_t a = 0; a < slot.keys.size(); ++a) {
    const Variable& va = vars_[slot.keys[a].var];
    if (va.role != Role::kReduced) continue;
    g_r_.segment(va.dx_offset, va.tangent) += gr.segment(slot.constant_col[a], va.tangent);
    for (std::size_t c = 0; c < slot.keys.size(); ++c) {
      const Variable& vc = vars_[slot.keys[c].var];
      if (vc.role != Role::kReduced || va.dx_offset > vc.dx_offset) continue;
      H_rr_.block(va.dx_offset, vc.dx_offset, va.tangent, vc.tangent) +=
          JtJ.block(slot.constant_col[a], slot.constant_col[c], va.tangent, vc.tangent);
    }
  }
}

// (J^T J + diag / radius) dx = -J^T r with the eliminated variables Schur-complemented out.
bool SchurLm::solveStep(double radius) {
  S_ = H_rr_;
  S_.diagonal() += diagonal_.head(num_reduced_) / radius;
  Eigen::VectorXd rhs = -g_r_;
  for (EliminatedBlock& b : elim_) {
    const Variable& e = vars_[b.var];
    if (e.tangent == 3) {
      Eigen::Matrix3d A = b.H;
      A.diagonal() += diagonal_.segment<3>(e.dx_offset) / radius;
      const Eigen::LLT<Eigen::Matrix3d> llt(A);
      if (llt.info() != Eigen::Success) return false;
      b.A_inv = llt.solve(Eigen::Matrix3d::Identity());
    } else {
      Eigen::MatrixXd A = b.H;
      A.diagonal() += diagonal_.segment(e.dx_offset, e.tangent) / radius;
      const Eigen::LLT<Eigen::MatrixXd> llt(A);
      if (llt.info() != Eigen::Success) return false;
      b.A_inv = llt.solve(Eigen::MatrixXd::Identity(e.tangent, e.tangent));
    }
    // rhs += V_a g_e and S -= V_a W_b^T over pairs of uses (upper triangle), V = W A^-1.
    uses_.clear();
    for (const auto& [si, pi] : b.uses) {
      const Slot& slot = slots_[si];
      const Variable& v = vars_[slot.keys[pi].var];
      const double* W = W_.data() + slot.keys[pi].w_offset;
      double* V = V_.data() + slot.keys[pi].w_offset;
      double* rhs_v = rhs.data() + v.dx_offset;
      if (e.tangent == 3 && v.tangent == 6) {
        landmarkV<6>(W, b.A_inv.data(), b.g.data(), V, rhs_v);
      } else if (e.tangent == 3 && v.tangent == 3) {
        landmarkV<3>(W, b.A_inv.data(), b.g.data(), V, rhs_v);
      } else {
        RowMap Vm(V, v.tangent, e.tangent);
        Vm.noalias() = ConstRowMap(W, v.tangent, e.tangent).lazyProduct(b.A_inv);
        rhs.segment(v.dx_offset, v.tangent).noalias() += Vm.lazyProduct(b.g);
      }
      uses_.push_back({v.dx_offset, v.tangent, W, V});
    }
    for (const UseRef& ui : uses_) {
      double vt[18];  // a landmark's V by columns, once per use, for the vectorized kernel
      const bool by_columns = e.tangent == 3 && landmarkColumns(ui.V, ui.tangent, vt);
      for (const UseRef& uj : uses_) {
        if (ui.dx_offset > uj.dx_offset) continue;
        if (!by_columns || !subtractColumns3(&S_, ui.dx_offset, uj.dx_offset, ui.tangent, uj.tangent, vt, uj.W))
          subtractProduct(&S_, ui.dx_offset, uj.dx_offset, ui.tangent, uj.tangent, e.tangent, ui.V, uj.W);
      }
    }
  }
  if (!cholesky_.factorize(&S_, block_offsets_, block_sizes_)) return false;
  cholesky_.solve(&rhs);
  dx_.head(num_reduced_) = rhs;
  for (const EliminatedBlock& b : elim_) {
    const Variable& e = vars_[b.var];
    Eigen::VectorXd t = -b.g;
    for (const auto& [s, p] : b.uses) {
      const Slot& slot = slots_[s];
      const Variable& v = vars_[slot.keys[p].var];
      const double* w = W_.data() + slot.keys[p].w_offset;
      if (e.tangent == 3 && subtractLandmarkWtd(t.data(), w, v.tangent, dx_.data() + v.dx_offset))
        continue;
      t.noalias() -= ConstRowMap(w, v.tangent, e.tangent).transpose() * dx_.segment(v.dx_offset, v.tangent);
    }
    dx_.segment(e.dx_offset, e.tangent).noalias() = b.A_inv * t;
  }
  return dx_.allFinite();
}

// Ceres' model cost change: -(J dx)^T (r + J dx / 2), summed over the factors.
double SchurLm::modelCostChange() {
  double change = 0.0;
  for (const Slot& slot : slots_) {
    auto jd = jd_.head(slot.dim);
    jd.setZero();
    for (std::size_t p = 0; p < slot.keys.size(); ++p) {
      const Variable& v = vars_[slot.keys[p].var];
      if (v.role == Role::kConstant) continue;
      if (slot.constant.J)
        jd.noalias() += slot.constant.J->middleCols(slot.constant_col[p], v.tangent) *
                        dx_.segment(v.dx_offset, v.tangent);
      else if (slot.dim != 2 || !addTwoRowProduct(jd.data(), J_.data() + slot.keys[p].j_offset,
                                                  v.tangent, dx_.data() + v.dx_offset))
        jd.noalias() += ConstRowMap(J_.data() + slot.keys[p].j_offset, slot.dim, v.tangent) *
                        dx_.segment(v.dx_offset, v.tangent);
    }
    const ConstVecMap r(r_.data() + slot.r_offset, slot.dim);
    change -= jd.dot(r + 0.5 * jd);
  }
  return change;
}

void SchurLm::stepFrom(const std::vector<double>& x, std::vector<double>* out) const {
  *out = x;
  for (const Variable& v : vars_) {
    if (v.role != Role::kReduced && v.role != Role::kEliminated) continue;
    const double* xv = x.data() + v.x_offset;
    double* ov = out->data() + v.x_offset;
    const double* d = dx_.data() + v.dx_offset;
    if (v.manifold)
      v.manifold->Plus(xv, d, ov);
    else
      for (int i = 0; i < v.ambient; ++i) ov[i] = xv[i] + d[i];
  }
}

OptimizeResult SchurLm::run() {
  const auto start = std::chrono::steady_clock::now();
  OptimizeResult result;
  ceres::Solver::Summary& summary = result.summary;
  summary.num_residual_blocks = static_cast<int>(slots_.size());
  summary.num_parameter_blocks = static_cast<int>(vars_.size());
  summary.num_effective_parameters_reduced = num_step_;
  summary.num_linear_solves = 0;
  double cost = 0.0;
  if (!evaluate(x_, true, &cost)) {
    summary.termination_type = ceres::FAILURE;
    summary.message = "residual or Jacobian evaluation failed at the initial point";
    summary.initial_cost = summary.final_cost = std::numeric_limits<double>::quiet_NaN();
    return result;
  }
  summary.initial_cost = cost;
  buildNormalEquations();
  double radius = options_.initial_trust_region_radius, decrease_factor = 2.0;
  ceres::IterationSummary it0;
  it0.cost = cost;
  it0.trust_region_radius = radius;
  it0.step_is_successful = false;
  summary.iterations.push_back(it0);
  const auto x_norm = [&] {
    double s = 0.0;
    for (double v : x_) s += v * v;
    return std::sqrt(s);
  };
  summary.termination_type = ceres::NO_CONVERGENCE;
  summary.message = "maximum number of iterations reached";
  int invalid = 0, successful_steps = 0;
  for (int iteration = 1; iteration <= options_.max_iterations; ++iteration) {
    ceres::IterationSummary it;
    it.iteration = iteration;
    it.cost = cost;
    bool valid = solveStep(radius);
    ++summary.num_linear_solves;
    const double model_change = valid ? modelCostChange() : 0.0;
    // What the damping took of the step's model decrease, dx^T D dx (D = diagonal / radius).
    const double damping = (diagonal_.array() * dx_.array().square()).sum() / radius;
    valid = valid && model_change > 0.0;
    // A rejected or invalid step shrinks the trust region (Ceres' StepRejected); true: stop.
    const auto reject = [&] {
      radius /= decrease_factor;
      decrease_factor *= 2.0;
      it.trust_region_radius = radius;
      summary.iterations.push_back(it);
      if (radius >= kMinRadius) return false;
      summary.termination_type = ceres::CONVERGENCE;
      summary.message = "trust region radius below its minimum";
      return true;
    };
    if (!valid) {
      if (++invalid > kMaxConsecutiveInvalidSteps) {
        summary.termination_type = ceres::FAILURE;
        summary.message = "too many consecutive invalid steps";
        break;
      }
      if (reject()) break;
      continue;
    }
    invalid = 0;
    // A candidate whose cost cannot be evaluated (a landmark behind the camera, say) is an
    // unsuccessful step, as in Ceres, not an invalid one.
    stepFrom(x_, &candidate_);
    double candidate_cost = 0.0;
    if (!evaluate(candidate_, false, &candidate_cost)) candidate_cost = std::numeric_limits<double>::max();
    it.step_norm = dx_.norm();
    it.cost_change = cost - candidate_cost;
    // As Ceres, a solve that ends on a tolerance does not record that last iteration, and the
    // parameter tolerance applies only once a step was taken (Ceres' x_norm_ is -1 before).
    if (successful_steps > 0 && it.step_norm <= kParameterTolerance * (x_norm() + kParameterTolerance)) {
      summary.termination_type = ceres::CONVERGENCE;
      summary.message = "parameter tolerance reached";
      break;
    }
    if (std::abs(it.cost_change) <= options_.function_tolerance * cost) {
      summary.termination_type = ceres::CONVERGENCE;
      summary.message = "function tolerance reached";
      break;
    }
    const double relative_decrease = it.cost_change / model_change;
    it.relative_decrease = relative_decrease;
    if (relative_decrease > kMinRelativeDecrease) {
      ++successful_steps;
      x_.swap(candidate_);
      if (!evaluate(x_, true, &cost)) {  // cannot happen after a finite cost, but be safe
        summary.termination_type = ceres::FAILURE;
        summary.message = "Jacobian evaluation failed";
        break;
      }
      buildNormalEquations();
      const double q = 2.0 * relative_decrease - 1.0;
      radius = std::min(kMaxRadius, radius / std::max(1.0 / 3.0, 1.0 - q * q * q));
      decrease_factor = 2.0;
      it.step_is_successful = true;
      it.cost = cost;
      it.trust_region_radius = radius;
      summary.iterations.push_back(it);
      // A nearly undamped step that lowered the cost by what the quadratic model predicted, both
      // to within the function tolerance: the cost is quadratic here and the step went to the
      // model's minimum, so the next step could lower it by about the mismatch and the damping,
      // below the tolerance. Ceres computes that step only to find so.
      const double tolerance = options_.function_tolerance * cost;
      if (std::abs(it.cost_change - model_change) <= tolerance && damping <= tolerance) {
        summary.termination_type = ceres::CONVERGENCE;
        summary.message = "the step's decrease matched the model's within the function tolerance";
        break;
      }
      Eigen::VectorXd g(num_step_);
      g.head(num_reduced_) = g_r_;
      for (const EliminatedBlock& b : elim_) g.segment(vars_[b.var].dx_offset, b.g.size()) = b.g;
      if (g.lpNorm<Eigen::Infinity>() <= kGradientTolerance) {
        summary.termination_type = ceres::CONVERGENCE;
        summary.message = "gradient tolerance reached";
        break;
      }
    } else if (reject()) {
      break;
    }
  }
  summary.final_cost = cost;
  summary.total_time_in_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.usable = summary.termination_type != ceres::FAILURE && std::isfinite(summary.final_cost);
  return result;
}

void SchurLm::copyTo(Values* values) const {
  for (const Variable& v : vars_)
    if (v.role == Role::kReduced || v.role == Role::kEliminated)
      std::copy_n(x_.data() + v.x_offset, v.ambient, values->data(v.key));
}

}  // namespace

OptimizeResult optimizeSchurLm(const FactorGraph& graph, Values* values, const OptimizerOptions& options) {
  SchurLm solver(graph, *values, options);
  OptimizeResult result = solver.run();
  if (result.usable) solver.copyTo(values);
  return result;
}

}  // namespace hdvio
