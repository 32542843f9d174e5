#include "hdvio/backend/triangulation.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace hdvio {

TriangulationResult triangulate(const std::vector<Pose>& T_WC,
                                const std::vector<Vec3>& bearings_C) {
  TriangulationResult out;
  if (T_WC.size() < 2 || T_WC.size() != bearings_C.size()) return out;
  // Minimize the sum of squared distances to the rays: sum (I - d d^T)(x - c) = 0.
  Mat3 A = Mat3::Zero();
  Vec3 b = Vec3::Zero();
  std::vector<Vec3> dirs;
  for (std::size_t i = 0; i < T_WC.size(); ++i) {
    const Vec3 d = (T_WC[i].q * bearings_C[i]).normalized();
    dirs.push_back(d);
    const Mat3 P = Mat3::Identity() - d * d.transpose();
    A += P;
    b += P * T_WC[i].p;
  }
  for (std::size_t i = 0; i < dirs.size(); ++i)
    for (std::size_t j = i + 1; j < dirs.size(); ++j)
      out.max_ray_angle_rad =
          std::max(out.max_ray_angle_rad, std::acos(std::clamp(dirs[i].dot(dirs[j]), -1.0, 1.0)));
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(A);
  if (eig.eigenvalues()[0] < 1e-9 * std::max(1.0, eig.eigenvalues()[2])) return out;
  out.p_W = A.ldlt().solve(b);
  out.valid = out.p_W.allFinite();
  for (std::size_t i = 0; i < T_WC.size() && out.valid; ++i) {
    const Vec3 p_C = T_WC[i].inverse() * out.p_W;
    if (p_C.z() < 0.05 || p_C.normalized().dot(bearings_C[i].normalized()) < std::cos(0.05))
      out.valid = false;
  }
  return out;
}

}  // namespace hdvio
