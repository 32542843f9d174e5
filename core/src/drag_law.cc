#include "hdvio/core/drag_law.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>

namespace hdvio {

DragLaw fitDragLaw(const std::vector<Vec3>& u_body, const std::vector<double>& thrust,
                   const std::vector<Vec3>& force, const DragTerms& terms) {
  if (u_body.size() != force.size() || u_body.size() < 100 || (terms.rotor && thrust.size() != u_body.size()))
    throw std::invalid_argument("drag law fit: needs at least 100 velocity/thrust/force samples");
  if (!terms.linear && !terms.rotor && !terms.quadratic && !terms.lift)
    throw std::invalid_argument("drag law fit: no term to fit");
  // Per axis a, unknowns x = [d_a, r_a, c_a, k_h (z only)]:
  //   force_a = -(d_a + r_a s(T)) u_a - c_a |u| u_a (+ k_h (u_x^2 + u_y^2) on z).
  using Vec4 = Eigen::Vector4d;
  using Mat4 = Eigen::Matrix4d;
  const bool use[4] = {terms.linear, terms.rotor, terms.quadratic, terms.lift};
  Mat4 N[3];
  Vec4 b[3];
  for (int a = 0; a < 3; ++a) N[a].setZero(), b[a].setZero();
  for (std::size_t k = 0; k < u_body.size(); ++k) {
    const Vec3& u = u_body[k];
    const double s = terms.rotor ? DragLaw::rotorScale(thrust[k]) : 0.0;
    for (int a = 0; a < 3; ++a) {
      const Vec4 row(-u(a), -s * u(a), -u.norm() * u(a), a == 2 ? u.x() * u.x() + u.y() * u.y() : 0.0);
      N[a] += row * row.transpose();
      b[a] += row * force[k](a);
    }
  }
  DragLaw law;
  for (int a = 0; a < 3; ++a) {
    // Non-negative least squares in at most four unknowns: the optimum is the unconstrained
    // optimum on its own support, so the best feasible one over all supports is it.
    Vec4 best = Vec4::Zero();
    double best_cost = 0.0;  // cost of x = 0 (up to the constant)
    for (int support = 1; support < 16; ++support) {
      int idx[4], n = 0;
      bool allowed = true;
      for (int j = 0; j < 4; ++j)
        if (support & (1 << j)) allowed = allowed && use[j] && (j < 3 || a == 2), idx[n++] = j;
      if (!allowed) continue;
      Eigen::MatrixXd Ns(n, n);
      Eigen::VectorXd bs(n);
      for (int r = 0; r < n; ++r) {
        bs(r) = b[a](idx[r]);
        for (int c = 0; c < n; ++c) Ns(r, c) = N[a](idx[r], idx[c]);
      }
      const Eigen::VectorXd xs = Ns.ldlt().solve(bs);
      Vec4 x = Vec4::Zero();
      for (int r = 0; r < n; ++r) x(idx[r]) = xs(r);
      if ((x.array() < 0.0).any() || !x.allFinite()) continue;
      const double cost = x.dot(N[a] * x) - 2.0 * b[a].dot(x);
      if (cost < best_cost) best_cost = cost, best = x;
    }
    law.linear(a) = best(0);
    law.rotor(a) = best(1);
    law.quadratic(a) = best(2);
    if (a == 2) law.lift = best(3);
  }
  return law;
}

namespace {

// Per axis: variance v_k = sum_j c_j phi_jk with c_j = exp(theta_j) >= 0; minimizes the negative
// log-likelihood sum_k (log v_k + r_k^2 / v_k) / 2 by Fisher scoring (E[r^2] = v makes the
// expected Hessian PSD) with Levenberg damping and a step accepted only if the cost falls.
Eigen::VectorXd fitVarianceCoefficients(const Eigen::MatrixXd& phi, const Eigen::VectorXd& r2) {
  const Eigen::Index n = phi.cols(), m = phi.rows();
  const auto cost = [&](const Eigen::VectorXd& c) {
    const Eigen::VectorXd v = phi * c;
    return 0.5 * (v.array().log() + r2.array() / v.array()).sum();
  };
  const double mean_r2 = std::max(r2.mean(), 1e-12);
  Eigen::VectorXd theta(n);
  theta(0) = std::log(0.5 * mean_r2);  // column 0 is the constant
  for (Eigen::Index j = 1; j < n; ++j)
    theta(j) = std::log(0.5 * mean_r2 / std::max(phi.col(j).mean(), 1e-12) / static_cast<double>(n - 1));
  double f = cost(theta.array().exp().matrix());
  double lambda = 1e-3;
  for (int it = 0; it < 500 && lambda < 1e12; ++it) {
    const Eigen::VectorXd c = theta.array().exp().matrix();
    const Eigen::VectorXd v = phi * c;
    // d cost / d c_j = sum phi_jk (v_k - r_k^2) / (2 v_k^2); Fisher: sum phi_ik phi_jk / (2 v_k^2).
    const Eigen::VectorXd w = (0.5 / v.array().square()).matrix();
    const Eigen::VectorXd g_c = phi.transpose() * (w.array() * (v - r2).array()).matrix();
    const Eigen::MatrixXd F_c = phi.transpose() * w.asDiagonal() * phi;
    const Eigen::VectorXd g = c.cwiseProduct(g_c);
    Eigen::MatrixXd F = c.asDiagonal() * F_c * c.asDiagonal();
    F.diagonal() *= 1.0 + lambda;
    const Eigen::VectorXd step = F.ldlt().solve(-g);
    const Eigen::VectorXd next = (theta + step).cwiseMax(-60.0).cwiseMin(60.0);
    const double f_next = cost(next.array().exp().matrix());
    if (std::isfinite(f_next) && f_next <= f) {
      const bool converged = f - f_next <= 1e-12 * (std::abs(f) + static_cast<double>(m));
      theta = next, f = f_next, lambda = std::max(lambda / 3.0, 1e-9);
      if (converged) break;
    } else {
      lambda *= 4.0;
    }
  }
  // A term driven to the floor explains nothing: exactly zero (the constant keeps sigma > 0).
  Eigen::VectorXd c = theta.array().exp().matrix();
  for (Eigen::Index j = 1; j < n; ++j)
    if (theta(j) <= -60.0) c(j) = 0.0;
  return c;
}

}  // namespace

DragLaw withFittedSigma(DragLaw law, const std::vector<Vec3>& u_body, const std::vector<Vec3>& omega,
                        const std::vector<double>& thrust, const std::vector<Vec3>& force,
                        const DragSigmaTerms& terms) {
  const std::size_t m = u_body.size();
  if (force.size() != m || omega.size() != m || thrust.size() != m || m < 100)
    throw std::invalid_argument("drag sigma fit: needs at least 100 velocity/rate/thrust/force samples");
  const bool use[3] = {terms.speed, terms.rate, terms.thrust};
  const int n = 1 + use[0] + use[1] + use[2];
  Eigen::MatrixXd phi(m, n);
  Eigen::MatrixXd r2(m, 3);
  for (std::size_t k = 0; k < m; ++k) {
    const double dT = thrust[k] - DragLaw::kHoverThrust;
    const double all[3] = {u_body[k].squaredNorm(), omega[k].squaredNorm(), dT * dT};
    int col = 0;
    phi(k, col++) = 1.0;
    for (int j = 0; j < 3; ++j)
      if (use[j]) phi(k, col++) = all[j];
    r2.row(k) = (force[k] - law.force(u_body[k], thrust[k])).cwiseAbs2().transpose();
  }
  Vec3* const fields[3] = {&law.sigma_speed, &law.sigma_rate, &law.sigma_thrust};
  for (Vec3* f : fields) f->setZero();
  if (n == 1) {  // the maximum-likelihood constant is the residual's mean square
    Vec3 sum_sq = Vec3::Zero();
    for (std::size_t k = 0; k < m; ++k) sum_sq += r2.row(k).transpose();
    law.sigma = (sum_sq / static_cast<double>(m)).cwiseSqrt();
    return law;
  }
  for (int a = 0; a < 3; ++a) {
    const Eigen::VectorXd c = fitVarianceCoefficients(phi, r2.col(a));
    law.sigma(a) = std::sqrt(c(0));
    int col = 1;
    for (int j = 0; j < 3; ++j)
      if (use[j]) (*fields[j])(a) = std::sqrt(c(col++));
  }
  return law;
}

}  // namespace hdvio
