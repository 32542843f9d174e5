#include "hdvio/core/drag_law.h"

#include <stdexcept>

namespace hdvio {

DragLaw fitDragLaw(const std::vector<Vec3>& u_body, const std::vector<Vec3>& force) {
  if (u_body.size() != force.size() || u_body.size() < 100)
    throw std::invalid_argument("drag law fit: needs at least 100 velocity/force pairs");
  // Per axis a, unknowns x = [d_a, c_a]: force_a = -d_a u_a - c_a |u| u_a.
  Eigen::Matrix2d N[3];
  Eigen::Vector2d b[3];
  for (int a = 0; a < 3; ++a) N[a].setZero(), b[a].setZero();
  for (std::size_t k = 0; k < u_body.size(); ++k) {
    const Vec3& u = u_body[k];
    for (int a = 0; a < 3; ++a) {
      const Eigen::Vector2d row(-u(a), -u.norm() * u(a));
      N[a] += row * row.transpose();
      b[a] += row * force[k](a);
    }
  }
  DragLaw law;
  for (int a = 0; a < 3; ++a) {
    // Non-negative least squares in two unknowns: the best feasible of the unconstrained
    // solution and the boundary ones.
    const Eigen::Vector2d candidates[4] = {
        N[a].ldlt().solve(b[a]),
        Eigen::Vector2d(N[a](0, 0) > 0.0 ? b[a](0) / N[a](0, 0) : 0.0, 0.0),
        Eigen::Vector2d(0.0, N[a](1, 1) > 0.0 ? b[a](1) / N[a](1, 1) : 0.0),
        Eigen::Vector2d::Zero()};
    Eigen::Vector2d best = Eigen::Vector2d::Zero();
    double best_cost = 0.0;  // cost of x = 0 (up to the constant)
    for (const Eigen::Vector2d& x : candidates) {
      if ((x.array() < 0.0).any() || !x.allFinite()) continue;
      const double cost = x.dot(N[a] * x) - 2.0 * b[a].dot(x);
      if (cost < best_cost) best_cost = cost, best = x;
    }
    law.linear(a) = best(0);
    law.quadratic(a) = best(1);
  }
  return law;
}

}  // namespace hdvio
