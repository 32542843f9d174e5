#pragma once
// Factors: keys + residual + noise model, evaluated by Ceres.
//
// Most factors derive from FactorT (GTSAM's evaluateError shape): they write only the
// UNWHITENED residual and its Jacobians with respect to the TANGENT spaces of their variables;
// FactorT whitens both and lifts the Jacobians to the ambient parameter sizes Ceres expects.
// Nothing is mutated inside Evaluate; a factor is immutable once built.
#include <array>
#include <memory>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>
#include <ceres/sized_cost_function.h>

#include "hdvio/core/key.h"
#include "hdvio/core/manifolds.h"
#include "hdvio/core/noise_model.h"
#include "hdvio/core/values.h"

namespace hdvio {

// Whitened residual and tangent-space Jacobians of one factor at a linearization point.
struct Linearization {
  Eigen::VectorXd residual;
  std::vector<Eigen::MatrixXd> jacobians;  // one per key, dim x tangentDim(key)
};

class Factor {
 public:
  Factor(std::vector<Key> keys, NoiseModelPtr noise);
  virtual ~Factor() = default;
  Factor(const Factor&) = delete;
  Factor& operator=(const Factor&) = delete;

  const std::vector<Key>& keys() const { return keys_; }
  int dim() const { return noise_->dim(); }
  const NoiseModel& noiseModel() const { return *noise_; }
  ceres::LossFunction* loss() const { return noise_->loss(); }

  // The whitened cost function; its parameter blocks are the keys in order. Owned by the factor.
  virtual ceres::CostFunction* costFunction() const = 0;

  // Whitened residual at values (no robust loss); false if evaluation failed.
  bool whitenedError(const Values& values, Eigen::VectorXd* residual) const;
  double error(const Values& values) const;  // 0.5 * |whitened residual|^2
  // Whitened residual and tangent Jacobians (robust loss not applied).
  bool linearize(const Values& values, Linearization* out) const;
  // The same at raw parameter blocks x (one per key, ambient), for solvers that work in
  // tangent space: tangent_jacobians[i] (null if not wanted, or all null) is row-major
  // dim x tangentDim(key i); manifolds[i] is key i's (null: Euclidean). This default goes
  // through costFunction() and the manifolds' PlusJacobian; FactorT skips the ambient lift.
  virtual bool evaluateTangent(const double* const* x, const ceres::Manifold* const* manifolds,
                               double* residual, double** tangent_jacobians) const;
  // A factor whose whitened tangent Jacobian is the same at every point (a linearized prior)
  // gives it here (dim x the keys' tangent sizes in key order) with its J^T J, both computed
  // once, so a solver need not evaluate or multiply them per iteration. Null otherwise.
  struct ConstantJacobian {
    const Eigen::MatrixXd* J = nullptr;
    const Eigen::MatrixXd* JtJ = nullptr;
  };
  virtual ConstantJacobian constantJacobian() const { return {}; }

 private:
  std::vector<Key> keys_;
  NoiseModelPtr noise_;
};

using FactorPtr = std::shared_ptr<const Factor>;

// Derived must provide
//   bool evaluateError(const double* const* x, double* residual, double** tangent_jacobians) const;
// where x[i] is variable i's ambient parameter block, residual has kDim entries, and
// tangent_jacobians[i] (null if not wanted) is row-major kDim x Vars_i::kTangent.
// A factor whose noise is always block diagonal (NoiseModel::blockDiagonal) declares
//   static constexpr int kNoiseDenseBlock = K;
// and is then whitened with compile-time sizes; its constructor checks the model's shape.
template <class Derived, int kDim, class... Vars>
class FactorT : public Factor {
 public:
  static constexpr int kNumVars = sizeof...(Vars);
  static constexpr std::array<int, kNumVars> kTangent{Vars::kTangent...};
  static constexpr std::array<int, kNumVars> kAmbient{Vars::kAmbient...};
  static constexpr int kNoiseDenseBlock = 0;  // 0: whiten through NoiseModel's dynamic path

  FactorT(const std::array<Key, kNumVars>& keys, NoiseModelPtr noise)
      : Factor(std::vector<Key>(keys.begin(), keys.end()), std::move(noise)),
        cost_(std::make_unique<Cost>(this)) {
    constexpr int kBlock = Derived::kNoiseDenseBlock;
    if (kBlock > 0 && (noiseModel().dim() != kDim || noiseModel().denseBlock() != kBlock))
      throw std::logic_error("FactorT: noise model is not the block-diagonal shape the factor declares");
  }

  ceres::CostFunction* costFunction() const override { return cost_.get(); }

  bool evaluateTangent(const double* const* x, const ceres::Manifold* const*, double* residual,
                       double** tangent_jacobians) const override {
    const Derived& derived = static_cast<const Derived&>(*this);
    if (!derived.evaluateError(x, residual, tangent_jacobians)) return false;
    if constexpr (Derived::kNoiseDenseBlock > 0)
      noiseModel().template whitenResidualFixed<kDim, Derived::kNoiseDenseBlock>(residual);
    else if (noiseModel().denseBlock() == 0 && noiseModel().dim() == kDim)
      noiseModel().template whitenResidualDiagonal<kDim>(residual);
    else
      noiseModel().whitenResidual(residual);
    if (tangent_jacobians) whitenAll(tangent_jacobians, std::index_sequence_for<Vars...>{});
    return true;
  }

 private:
  template <std::size_t... I>
  void whitenAll(double** tangent, std::index_sequence<I...>) const {
    (whiten<Vars>(tangent[I]), ...);
  }
  template <class Var>
  void whiten(double* tangent_jacobian) const {
    if (!tangent_jacobian) return;
    if constexpr (Derived::kNoiseDenseBlock > 0)
      noiseModel().template whitenJacobianFixed<kDim, Derived::kNoiseDenseBlock, Var::kTangent>(
          tangent_jacobian);
    else if (noiseModel().denseBlock() == 0 && noiseModel().dim() == kDim)  // diagonal: fixed sizes
      noiseModel().template whitenJacobianDiagonal<kDim, Var::kTangent>(tangent_jacobian);
    else
      noiseModel().whitenJacobian(tangent_jacobian, Var::kTangent);
  }

  class Cost : public ceres::SizedCostFunction<kDim, Vars::kAmbient...> {
   public:
    // Holds the base pointer: the derived object does not exist yet while FactorT is built, so
    // the downcast happens only in Evaluate.
    explicit Cost(const FactorT* factor) : factor_(factor) {}
    bool Evaluate(double const* const* x, double* residual, double** jacobians) const override {
      const Derived& derived = static_cast<const Derived&>(*factor_);
      constexpr int kTangentTotal = (Vars::kTangent + ...);
      std::array<double, kDim * kTangentTotal> tangent_storage;
      std::array<double*, kNumVars> tangent{};
      int offset = 0;
      for (int i = 0; i < kNumVars; ++i) {
        tangent[i] = (jacobians && jacobians[i]) ? tangent_storage.data() + offset : nullptr;
        offset += kDim * kTangent[i];
      }
      if (!derived.evaluateError(x, residual, jacobians ? tangent.data() : nullptr)) return false;
      const NoiseModel& noise = factor_->noiseModel();
      if constexpr (Derived::kNoiseDenseBlock > 0)
        noise.whitenResidualFixed<kDim, Derived::kNoiseDenseBlock>(residual);
      else
        noise.whitenResidual(residual);
      if (!jacobians) return true;
      liftAll(x, jacobians, tangent.data(), std::index_sequence_for<Vars...>{});
      return true;
    }

   private:
    template <std::size_t... I>
    void liftAll(double const* const* x, double** jacobians, double** tangent,
                 std::index_sequence<I...>) const {
      (lift<Vars>(x[I], jacobians[I], tangent[I]), ...);
    }
    template <class Var>
    void lift(const double* x, double* ambient_jacobian, double* tangent_jacobian) const {
      if (!ambient_jacobian) return;
      if constexpr (Derived::kNoiseDenseBlock > 0)
        factor_->noiseModel().template whitenJacobianFixed<kDim, Derived::kNoiseDenseBlock, Var::kTangent>(
            tangent_jacobian);
      else
        factor_->noiseModel().whitenJacobian(tangent_jacobian, Var::kTangent);
      using TangentJ = Eigen::Matrix<double, kDim, Var::kTangent, Eigen::RowMajor>;
      using AmbientJ = Eigen::Matrix<double, kDim, Var::kAmbient, Eigen::RowMajor>;
      Eigen::Map<const TangentJ> Jt(tangent_jacobian);
      Eigen::Map<AmbientJ> Ja(ambient_jacobian);
      if constexpr (Var::kEuclidean) {
        Ja = Jt;
      } else {
        Eigen::Matrix<double, Var::kTangent, Var::kAmbient, Eigen::RowMajor> L;
        Var::lift(x, L.data());
        Ja.noalias() = Jt * L;
      }
    }
    const FactorT* factor_;
  };

  std::unique_ptr<Cost> cost_;
};

}  // namespace hdvio
