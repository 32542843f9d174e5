// ImoFilter::updateGeneric: an EKF update with an explicit residual and Jacobian, for
// measurements other than the clone displacements (gate-corner reprojections, docs/gate_io.md).
#include <cmath>
#include <stdexcept>

#include "hdvio/backend/imo/imo_filter.h"

namespace hdvio::imo {
namespace {

// Standard normal quantile by bisection on erfc (a few dozen evaluations, called once per update).
double normalQuantile(double p) {
  double lo = -12.0, hi = 12.0;
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

// Wilson-Hilferty: chi2_m quantile ~ m (1 - 2/(9m) + z sqrt(2/(9m)))^3, within 1 % for m >= 2
// at the 95-99.9 % levels used for gating.
double chiSquareQuantile(int dof, double probability) {
  const double m = dof;
  const double c = 2.0 / (9.0 * m);
  const double t = 1.0 - c + normalQuantile(probability) * std::sqrt(c);
  return m * t * t * t;
}

}  // namespace

MatX ImoFilter::jacobianInFilterConvention(const MatX& H_right) const {
  if (options_.rotation_error == RotationError::kRight) return H_right;
  MatX H = H_right;
  H.middleCols<3>(0) = H_right.middleCols<3>(0) * x_.R.transpose();
  for (std::size_t k = 0; k < clones_.size(); ++k) {
    const int o = kStateDim + kCloneDim * static_cast<int>(k);
    H.middleCols<3>(o) = H_right.middleCols<3>(o) * clones_[k].R.transpose();
  }
  return H;
}

UpdateOutcome ImoFilter::updateGeneric(const VecX& r, const MatX& H, const MatX& R, double gate_probability) {
  const int m = static_cast<int>(r.size());
  if (m == 0 || H.rows() != m || H.cols() != dim() || R.rows() != m || R.cols() != m)
    throw std::logic_error("ImoFilter::updateGeneric: inconsistent sizes");
  if (gate_probability >= 1.0) throw std::logic_error("ImoFilter::updateGeneric: gate probability must be < 1");
  syncCrossCovariance();
  const MatX PHt = cov() * H.transpose();  // n x m
  MatX S = H * PHt + R;
  S = 0.5 * (S + S.transpose());
  const Eigen::LDLT<MatX> S_ldlt(S);
  last_chi2_ = r.dot(S_ldlt.solve(r));
  if (gate_probability > 0.0 && last_chi2_ > chiSquareQuantile(m, gate_probability))
    return UpdateOutcome::kRejectedByGate;
  const MatX K = S_ldlt.solve(PHt.transpose()).transpose();  // n x m
  // Joseph form (I - KH) P (I - KH)' + K R K', evaluated as written (not expanded): it stays
  // positive semi-definite in floating point even when P is large after a long gap without
  // updates. O(n^3), cheap for the evolving state and a few clones.
  const MatX IKH = MatX::Identity(dim(), dim()) - K * H;
  const MatX P = IKH * cov() * IKH.transpose() + K * R * K.transpose();
  cov() = 0.5 * (P + P.transpose());
  inject(K * r);
  return UpdateOutcome::kApplied;
}

}  // namespace hdvio::imo
