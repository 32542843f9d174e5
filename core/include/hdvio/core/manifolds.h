#pragma once
// Ceres manifolds for hdvio's variable types, in the convention of lie.h:
// a pose is stored as [px py pz qx qy qz qw] and perturbed as (p + dp, q * Exp(dtheta)).
#include <memory>

#include <ceres/manifold.h>

namespace hdvio {

class PoseManifold final : public ceres::Manifold {
 public:
  static constexpr int kAmbient = 7;
  static constexpr int kTangent = 6;
  int AmbientSize() const override { return kAmbient; }
  int TangentSize() const override { return kTangent; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;

  // d(tangent)/d(ambient) at x, row-major 6x7: maps an ambient Jacobian back to tangent space.
  // Equals MinusJacobian; kept static so factors can lift without a virtual call.
  static void liftJacobian(const double* x, double* jacobian_6x7);
};

// Stateless shared instances (ceres keeps raw pointers; Values keeps these alive).
std::shared_ptr<ceres::Manifold> poseManifold();

// Variable types for the factor helper (factor.h): sizes and how to lift tangent Jacobians.
struct PoseVar {
  static constexpr int kAmbient = 7;
  static constexpr int kTangent = 6;
  static constexpr bool kEuclidean = false;
  static void lift(const double* x, double* jac) { PoseManifold::liftJacobian(x, jac); }
};

template <int N>
struct VectorVar {
  static constexpr int kAmbient = N;
  static constexpr int kTangent = N;
  static constexpr bool kEuclidean = true;
  static void lift(const double*, double*) {}
};

using Vec3Var = VectorVar<3>;
using BiasVar = VectorVar<6>;

}  // namespace hdvio
