#include "hdvio/backend/schur_marginalization.h"

#include <Eigen/Eigenvalues>
#include <map>
#include <stdexcept>

namespace hdvio {
namespace {

// Jacobi scaling 1/sqrt(diag): information in a VIO window spans many orders of magnitude
// (gyro-bias random walk ~1e10, a velocity prior ~1e2), so thresholds are applied to the
// diagonally normalized matrix, where "small" means small relative to that variable's own
// information.
Eigen::VectorXd jacobiScaling(const Eigen::MatrixXd& A) {
  return A.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
}

// Symmetric pseudo-inverse via eigen-decomposition of the scaled matrix with a threshold.
Eigen::MatrixXd pseudoInverse(const Eigen::MatrixXd& A, double threshold) {
  const Eigen::VectorXd s = jacobiScaling(A);
  const Eigen::MatrixXd As = s.asDiagonal() * (0.5 * (A + A.transpose())) * s.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(As);
  const Eigen::VectorXd& l = eig.eigenvalues();
  const Eigen::VectorXd inv = (l.array() > threshold).select(l.cwiseInverse(), 0.0);
  return s.asDiagonal() * eig.eigenvectors() * inv.asDiagonal() *
         eig.eigenvectors().transpose() * s.asDiagonal();
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

  const Eigen::MatrixXd Hmm_inv = pseudoInverse(sys.H.topLeftCorner(m, m), options.eigen_threshold);
  const Eigen::MatrixXd Hrm = sys.H.bottomLeftCorner(r, m);
  Eigen::MatrixXd H = sys.H.bottomRightCorner(r, r) - Hrm * Hmm_inv * Hrm.transpose();
  const Eigen::VectorXd b = sys.b.tail(r) - Hrm * Hmm_inv * sys.b.head(m);
  H = 0.5 * (H + H.transpose());

  // Factor H = J0^T J0 and b = J0^T r0 over the significant eigenvalues only. The scaling
  // comes from the information the remaining variables had before the elimination, so what
  // cancels in the complement (e.g. all a free variable carried) comes out as no information.
  const Eigen::VectorXd scale = jacobiScaling(sys.H.bottomRightCorner(r, r));
  const Eigen::MatrixXd Hs = scale.asDiagonal() * H * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Hs);
  const Eigen::VectorXd& l = eig.eigenvalues();
  std::vector<int> kept;
  for (int i = 0; i < l.size(); ++i)
    if (l[i] > options.eigen_threshold) kept.push_back(i);
  if (kept.empty()) return nullptr;
  Eigen::MatrixXd J0(kept.size(), r);
  Eigen::VectorXd r0(kept.size());
  const Eigen::VectorXd inv_scale = scale.cwiseInverse();
  for (std::size_t row = 0; row < kept.size(); ++row) {
    const int i = kept[row];
    const double sq = std::sqrt(l[i]);
    const Eigen::VectorXd u = eig.eigenvectors().col(i);
    // H = S^-1 U L U^T S^-1  =>  J0 rows sqrt(l) u^T S^-1;  b = J0^T r0  =>  r0 = u^T S b / sqrt(l).
    J0.row(row) = sq * u.cwiseProduct(inv_scale).transpose();
    r0[row] = u.cwiseProduct(scale).dot(b) / sq;
  }
  return std::make_shared<MarginalizationPrior>(remaining, values, std::move(J0), std::move(r0));
}

}  // namespace hdvio
