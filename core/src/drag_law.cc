#include "hdvio/core/drag_law.h"

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

}  // namespace hdvio
