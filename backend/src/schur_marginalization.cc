#include "hdvio/backend/schur_marginalization.h"

#include <Eigen/Eigenvalues>
#include <map>
#include <stdexcept>

namespace hdvio {
namespace {

// Symmetric pseudo-inverse via eigen-decomposition with a relative threshold.
Eigen::MatrixXd pseudoInverse(const Eigen::MatrixXd& A, double rel_threshold) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (A + A.transpose()));
  const Eigen::VectorXd& l = eig.eigenvalues();
  const double cut = rel_threshold * std::max(l.cwiseAbs().maxCoeff(), 1e-300);
  const Eigen::VectorXd inv = (l.array() > cut).select(l.cwiseInverse(), 0.0);
  return eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
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
    Linearization lin;
    if (!factor->linearize(values, &lin))
      throw std::runtime_error("marginalization: a factor could not be linearized");
    if (const ceres::LossFunction* loss = factor->loss()) {
      // First-order robust weighting (Triggs correction without the curvature term).
      double rho[3];
      loss->Evaluate(lin.residual.squaredNorm(), rho);
      const double w = std::sqrt(std::max(rho[1], 0.0));
      lin.residual *= w;
      for (auto& J : lin.jacobians) J *= w;
    }
    const auto& fkeys = factor->keys();
    for (std::size_t a = 0; a < fkeys.size(); ++a) {
      const auto ia = offset_of.find(fkeys[a]);
      if (ia == offset_of.end()) throw std::logic_error("linearizeDense: key outside the system");
      const Eigen::MatrixXd& Ja = lin.jacobians[a];
      sys.b.segment(ia->second, Ja.cols()) += Ja.transpose() * lin.residual;
      for (std::size_t c = 0; c < fkeys.size(); ++c) {
        const int ic = offset_of.at(fkeys[c]);
        const Eigen::MatrixXd& Jc = lin.jacobians[c];
        sys.H.block(ia->second, ic, Ja.cols(), Jc.cols()) += Ja.transpose() * Jc;
      }
    }
  }
  return sys;
}

std::shared_ptr<MarginalizationPrior> marginalizeBySchurComplement(
    const FactorGraph& factors, const Values& values, const std::set<Key>& marginalized,
    const MarginalizationOptions& options) {
  // Order: removed variables first, then the Markov blanket.
  std::vector<Key> order(marginalized.begin(), marginalized.end());
  std::vector<Key> remaining;
  for (Key k : factors.keys())
    if (!marginalized.count(k)) remaining.push_back(k);
  if (remaining.empty()) return nullptr;
  order.insert(order.end(), remaining.begin(), remaining.end());

  const LinearSystem sys = linearizeDense(factors, values, order);
  int m = 0;
  for (Key k : marginalized) m += values.tangentDim(k);
  const int r = static_cast<int>(sys.H.rows()) - m;

  const Eigen::MatrixXd Hmm_inv = pseudoInverse(sys.H.topLeftCorner(m, m),
                                                options.relative_eigen_threshold);
  const Eigen::MatrixXd Hrm = sys.H.bottomLeftCorner(r, m);
  Eigen::MatrixXd H = sys.H.bottomRightCorner(r, r) - Hrm * Hmm_inv * Hrm.transpose();
  const Eigen::VectorXd b = sys.b.tail(r) - Hrm * Hmm_inv * sys.b.head(m);
  H = 0.5 * (H + H.transpose());

  // Factor H = J0^T J0 and b = J0^T r0 over the positive eigenvalues only.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
  const Eigen::VectorXd& l = eig.eigenvalues();
  // Relative to the scale of the whole system: what cancels in the complement (e.g. the
  // information a free variable carried) must come out as exactly no information.
  const double scale = std::max(sys.H.diagonal().maxCoeff(), 1e-300);
  const double cut = options.relative_eigen_threshold * scale;
  std::vector<int> kept;
  for (int i = 0; i < l.size(); ++i)
    if (l[i] > cut) kept.push_back(i);
  if (kept.empty()) return nullptr;
  Eigen::MatrixXd J0(kept.size(), r);
  Eigen::VectorXd r0(kept.size());
  for (std::size_t row = 0; row < kept.size(); ++row) {
    const int i = kept[row];
    const double s = std::sqrt(l[i]);
    J0.row(row) = s * eig.eigenvectors().col(i).transpose();
    r0[row] = eig.eigenvectors().col(i).dot(b) / s;
  }
  return std::make_shared<MarginalizationPrior>(remaining, values, std::move(J0), std::move(r0));
}

}  // namespace hdvio
