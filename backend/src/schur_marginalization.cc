#include "hdvio/backend/schur_marginalization.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <map>
#include <stdexcept>

namespace hdvio {
namespace {

// Jacobi scaling 1/sqrt(diag): information in a VIO window spans many orders of magnitude
// (gyro-bias random walk ~1e10, a velocity prior ~1e2), so thresholds are applied to the
// diagonally normalized matrix, where "small" means small relative to that variable's own
// information.
Eigen::VectorXd jacobiScaling(const Eigen::VectorXd& diagonal) {
  return diagonal.cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
}

// Symmetric pseudo-inverse via eigen-decomposition of the scaled matrix with a threshold.
Eigen::MatrixXd pseudoInverse(const Eigen::MatrixXd& A, double threshold) {
  if (A.rows() == 0) return A;
  const Eigen::VectorXd s = jacobiScaling(A.diagonal());
  const Eigen::MatrixXd As = s.asDiagonal() * (0.5 * (A + A.transpose())) * s.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(As);
  const Eigen::VectorXd& l = eig.eigenvalues();
  const Eigen::VectorXd inv = (l.array() > threshold).select(l.cwiseInverse(), 0.0);
  const Eigen::MatrixXd V = s.asDiagonal() * eig.eigenvectors();
  return V * inv.asDiagonal() * V.transpose();
}

// Hs = Js^T Js and bs = Js^T rs over the pivots above the threshold, by a Cholesky
// factorization with full diagonal pivoting (the largest remaining diagonal of the updated
// matrix first). Once that is below the threshold, so is everything left (Hs is positive
// semidefinite): those directions carry no information and are dropped, as eigenvalues below
// the threshold were. Several times cheaper than an eigen-decomposition of the same ~100x100
// matrix. False if nothing is significant.
bool squareRootFactor(Eigen::MatrixXd A, const Eigen::VectorXd& bs, double threshold,
                      Eigen::MatrixXd* Js, Eigen::VectorXd* rs) {
  const int n = static_cast<int>(A.rows());
  std::vector<int> perm(n);
  for (int i = 0; i < n; ++i) perm[i] = i;
  int k = 0;
  for (; k < n; ++k) {
    int j = k;
    A.diagonal().tail(n - k).maxCoeff(&j);
    j += k;
    if (!(A(j, j) > threshold)) break;
    if (j != k) {
      A.row(k).swap(A.row(j));
      A.col(k).swap(A.col(j));
      std::swap(perm[k], perm[j]);
    }
    const double pivot = std::sqrt(A(k, k));
    A(k, k) = pivot;
    const int m = n - k - 1;
    A.col(k).tail(m) /= pivot;
    A.bottomRightCorner(m, m).noalias() -= A.col(k).tail(m) * A.col(k).tail(m).transpose();
  }
  if (k == 0) return false;
  // P Hs P^T = L L^T over the first k columns: Js = L^T P, and L_kk rs = (P bs)_k.
  Js->setZero(k, n);
  Eigen::VectorXd Pb(n);
  for (int i = 0; i < n; ++i) {
    Pb[i] = bs[perm[i]];
    for (int c = 0; c < std::min(i + 1, k); ++c) (*Js)(c, perm[i]) = A(i, c);
  }
  *rs = A.topLeftCorner(k, k).triangularView<Eigen::Lower>().solve(Pb.head(k));
  return true;
}

// Whitened, first-order robustified linearization of one factor (Triggs correction without the
// curvature term, as Ceres does to first order).
Linearization linearizeRobust(const Factor& factor, const Values& values) {
  Linearization lin;
  if (!factor.linearize(values, &lin))
    throw std::runtime_error("marginalization: a factor could not be linearized");
  if (const ceres::LossFunction* loss = factor.loss()) {
    double rho[3];
    loss->Evaluate(lin.residual.squaredNorm(), rho);
    const double w = std::sqrt(std::max(rho[1], 0.0));
    lin.residual *= w;
    for (auto& J : lin.jacobians) J *= w;
  }
  return lin;
}

// A variable eliminated on its own before the dense step: its diagonal block, gradient and
// its blocks with the variables of the dense system (offsets there).
struct SparseVariable {
  Eigen::MatrixXd H;
  Eigen::VectorXd b;
  std::vector<std::pair<int, Eigen::MatrixXd>> coupling;  // (offset, H_ae)
};

void addCoupling(SparseVariable* v, int offset, const Eigen::MatrixXd& block) {
  for (auto& [o, H] : v->coupling)
    if (o == offset) {
      H += block;
      return;
    }
  v->coupling.emplace_back(offset, block);
}

// Marginalized variables of at most 3 dimensions (landmarks) that share no factor with each
// other, chosen greedily in key order: their block of H is block diagonal.
std::set<Key> independentSmallVariables(const FactorGraph& factors, const Values& values,
                                         const std::set<Key>& marginalized) {
  std::map<Key, std::set<Key>> neighbours;  // marginalized key -> marginalized keys it shares a factor with
  for (const auto& f : factors)
    for (Key a : f->keys())
      if (marginalized.count(a))
        for (Key c : f->keys())
          if (c != a && marginalized.count(c)) neighbours[a].insert(c);
  std::set<Key> chosen;
  for (Key k : marginalized) {
    if (values.tangentDim(k) > 3) continue;
    bool free = true;
    for (Key n : neighbours[k]) free = free && !chosen.count(n);
    if (free) chosen.insert(k);
  }
  return chosen;
}

}  // namespace

LinearSystem linearizeDense(const FactorGraph& factors, const Values& values,
                            const std::vector<Key>& keys) {
  LinearSystem sys;
  sys.keys = keys;
  std::map<Key, int> offset_of;
  int n = 0;
  for (Key k : keys) {
    sys.offsets.push_back(n);
    offset_of[k] = n;
    n += values.tangentDim(k);
  }
  sys.H = Eigen::MatrixXd::Zero(n, n);
  sys.b = Eigen::VectorXd::Zero(n);
  for (const auto& factor : factors) {
    const Linearization lin = linearizeRobust(*factor, values);
    const auto& fkeys = factor->keys();
    for (std::size_t a = 0; a < fkeys.size(); ++a) {
      const auto ia = offset_of.find(fkeys[a]);
      if (ia == offset_of.end()) throw std::logic_error("linearizeDense: key outside the system");
      const Eigen::MatrixXd& Ja = lin.jacobians[a];
      sys.b.segment(ia->second, Ja.cols()) += Ja.transpose() * lin.residual;
      for (std::size_t c = 0; c < fkeys.size(); ++c) {
        const int ic = offset_of.at(fkeys[c]);
        const Eigen::MatrixXd& Jc = lin.jacobians[c];
        sys.H.block(ia->second, ic, Ja.cols(), Jc.cols()).noalias() += Ja.transpose() * Jc;
      }
    }
  }
  return sys;
}

std::shared_ptr<MarginalizationPrior> marginalizeBySchurComplement(
    const FactorGraph& factors, const Values& values, const std::set<Key>& marginalized,
    const MarginalizationOptions& options) {
  std::vector<Key> remaining;
  for (Key k : factors.keys())
    if (!marginalized.count(k)) remaining.push_back(k);
  if (remaining.empty()) return nullptr;

  // 1. Linearize. Variables in `sparse` (landmarks) keep their own small blocks; everything
  //    else goes into a dense system ordered: other removed variables, then the Markov blanket.
  const std::set<Key> sparse = options.eliminate_independent_first
                                   ? independentSmallVariables(factors, values, marginalized)
                                   : std::set<Key>();
  std::vector<Key> order;
  for (Key k : marginalized)
    if (!sparse.count(k)) order.push_back(k);
  const int m_dense = [&] {
    int m = 0;
    for (Key k : order) m += values.tangentDim(k);
    return m;
  }();
  order.insert(order.end(), remaining.begin(), remaining.end());
  std::map<Key, int> offset_of;
  int n = 0;
  for (Key k : order) {
    offset_of[k] = n;
    n += values.tangentDim(k);
  }
  const int r = n - m_dense;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
  std::map<Key, SparseVariable> sparse_vars;
  for (const auto& factor : factors) {
    const Linearization lin = linearizeRobust(*factor, values);
    const auto& fkeys = factor->keys();
    int s = -1;  // the factor's sparse variable, if any (at most one by construction)
    for (std::size_t a = 0; a < fkeys.size(); ++a)
      if (sparse.count(fkeys[a])) s = static_cast<int>(a);
    if (s >= 0) {
      const Eigen::MatrixXd& Js = lin.jacobians[s];
      SparseVariable& v = sparse_vars[fkeys[s]];
      if (v.H.size() == 0) {
        v.H = Eigen::MatrixXd::Zero(Js.cols(), Js.cols());
        v.b = Eigen::VectorXd::Zero(Js.cols());
      }
      v.H.noalias() += Js.transpose() * Js;
      v.b.noalias() += Js.transpose() * lin.residual;
      for (std::size_t a = 0; a < fkeys.size(); ++a)
        if (static_cast<int>(a) != s)
          addCoupling(&v, offset_of.at(fkeys[a]), lin.jacobians[a].transpose() * Js);
    }
    // The factor's other Jacobians side by side: one product for its whole block of H (a
    // prior over the window is ~100 x 150: block by block that is a hundred small products).
    std::vector<std::pair<int, int>> columns;  // (offset in H, width), in the factor's key order
    int width = 0;
    for (std::size_t a = 0; a < fkeys.size(); ++a) {
      if (static_cast<int>(a) == s) continue;
      columns.emplace_back(offset_of.at(fkeys[a]), static_cast<int>(lin.jacobians[a].cols()));
      width += columns.back().second;
    }
    Eigen::MatrixXd J(lin.residual.size(), width);
    for (std::size_t a = 0, col = 0; a < fkeys.size(); ++a) {
      if (static_cast<int>(a) == s) continue;
      J.middleCols(col, lin.jacobians[a].cols()) = lin.jacobians[a];
      col += lin.jacobians[a].cols();
    }
    Eigen::MatrixXd JtJ = Eigen::MatrixXd::Zero(width, width);
    JtJ.selfadjointView<Eigen::Lower>().rankUpdate(J.transpose());
    JtJ.triangularView<Eigen::StrictlyUpper>() = JtJ.transpose();
    const Eigen::VectorXd Jtr = J.transpose() * lin.residual;
    for (std::size_t a = 0, ra = 0; a < columns.size(); ra += columns[a].second, ++a) {
      const auto [ia, wa] = columns[a];
      b.segment(ia, wa) += Jtr.segment(ra, wa);
      for (std::size_t c = 0, rc = 0; c < columns.size(); rc += columns[c].second, ++c)
        H.block(ia, columns[c].first, wa, columns[c].second) += JtJ.block(ra, rc, wa, columns[c].second);
    }
  }
  // The final factorization is scaled by the information the remaining variables had before
  // any elimination, so what cancels in the complement comes out as no information.
  const Eigen::VectorXd scale = jacobiScaling(H.diagonal().tail(r));

  // 2. Eliminate the sparse variables one by one: each is a Schur complement onto the few
  //    variables it touches (a landmark: the poses that observe it), linear in their number.
  for (const auto& [key, v] : sparse_vars) {
    const Eigen::MatrixXd Hinv = pseudoInverse(v.H, options.eigen_threshold);
    for (const auto& [oa, Ha] : v.coupling) {
      const Eigen::MatrixXd G = Ha * Hinv;
      b.segment(oa, G.rows()).noalias() -= G * v.b;
      for (const auto& [oc, Hc] : v.coupling)
        H.block(oa, oc, G.rows(), Hc.rows()).noalias() -= G * Hc.transpose();
    }
  }

  // 3. Dense Schur complement of the other removed variables (a state: ~15-18 dimensions).
  Eigen::MatrixXd Hr = H.bottomRightCorner(r, r);
  Eigen::VectorXd br = b.tail(r);
  if (m_dense > 0) {
    const Eigen::MatrixXd Hmm_inv = pseudoInverse(H.topLeftCorner(m_dense, m_dense), options.eigen_threshold);
    const Eigen::MatrixXd G = H.bottomLeftCorner(r, m_dense) * Hmm_inv;
    Hr.noalias() -= G * H.topRightCorner(m_dense, r);
    br.noalias() -= G * b.head(m_dense);
  }
  Hr = 0.5 * (Hr + Hr.transpose());

  // 4. Factor Hr = J0^T J0 and br = J0^T r0 over the significant directions only.
  Eigen::MatrixXd Js;
  Eigen::VectorXd r0;
  if (!squareRootFactor(scale.asDiagonal() * Hr * scale.asDiagonal(), scale.cwiseProduct(br),
                        options.eigen_threshold, &Js, &r0))
    return nullptr;
  Eigen::MatrixXd J0 = Js * scale.cwiseInverse().asDiagonal();  // H = S^-1 Hs S^-1
  return std::make_shared<MarginalizationPrior>(remaining, values, std::move(J0), std::move(r0));
}

}  // namespace hdvio
