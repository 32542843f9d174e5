#include "hdvio/core/values.h"

#include <stdexcept>

#include "hdvio/core/manifolds.h"

namespace hdvio {

void Values::insert(Key key, const Eigen::VectorXd& ambient,
                    std::shared_ptr<ceres::Manifold> manifold) {
  if (vars_.count(key)) throw std::logic_error("Values::insert: key " + key.str() + " exists");
  if (manifold && manifold->AmbientSize() != ambient.size())
    throw std::logic_error("Values::insert: size does not match manifold for " + key.str());
  vars_.emplace(key, Variable{ambient, std::move(manifold)});
}

void Values::insertPose(Key key, const Pose& pose) {
  Eigen::VectorXd x(7);
  x << pose.p, pose.q.normalized().coeffs();
  insert(key, x, poseManifold());
}

void Values::insertVector(Key key, const Eigen::VectorXd& value) { insert(key, value, nullptr); }

void Values::update(Key key, const Eigen::VectorXd& ambient) {
  Variable& v = at(key);
  if (v.ambient.size() != ambient.size())
    throw std::logic_error("Values::update: size mismatch for " + key.str());
  v.ambient = ambient;
}

void Values::updatePose(Key key, const Pose& pose) {
  Eigen::VectorXd x(7);
  x << pose.p, pose.q.normalized().coeffs();
  update(key, x);
}

void Values::erase(Key key) { vars_.erase(key); }

void Values::merge(const Values& other) {
  for (const auto& [key, var] : other.vars_) vars_[key] = var;
}

Values Values::subset(const std::vector<Key>& keys) const {
  Values out;
  for (Key k : keys) out.vars_[k] = at(k);
  return out;
}

std::vector<Key> Values::keys() const {
  std::vector<Key> out;
  out.reserve(vars_.size());
  for (const auto& kv : vars_) out.push_back(kv.first);
  return out;
}

const Values::Variable& Values::at(Key key) const {
  auto it = vars_.find(key);
  if (it == vars_.end()) throw std::out_of_range("Values: no variable " + key.str());
  return it->second;
}

Values::Variable& Values::at(Key key) {
  auto it = vars_.find(key);
  if (it == vars_.end()) throw std::out_of_range("Values: no variable " + key.str());
  return it->second;
}

Pose Values::pose(Key key) const {
  const Variable& v = at(key);
  if (v.ambient.size() != 7) throw std::logic_error("Values::pose: " + key.str() + " is not a pose");
  return Pose(Quat(v.ambient[6], v.ambient[3], v.ambient[4], v.ambient[5]), v.ambient.head<3>());
}

Eigen::VectorXd Values::vector(Key key) const { return at(key).ambient; }

Vec3 Values::vec3(Key key) const {
  const Variable& v = at(key);
  if (v.ambient.size() != 3) throw std::logic_error("Values::vec3: " + key.str() + " is not 3-D");
  return v.ambient;
}

double* Values::data(Key key) { return at(key).ambient.data(); }
const double* Values::data(Key key) const { return at(key).ambient.data(); }
int Values::ambientDim(Key key) const { return static_cast<int>(at(key).ambient.size()); }

int Values::tangentDim(Key key) const {
  const Variable& v = at(key);
  return v.manifold ? v.manifold->TangentSize() : static_cast<int>(v.ambient.size());
}

ceres::Manifold* Values::manifold(Key key) const { return at(key).manifold.get(); }

Eigen::VectorXd Values::plus(Key key, const Eigen::VectorXd& delta) const {
  const Variable& v = at(key);
  if (!v.manifold) return v.ambient + delta;
  Eigen::VectorXd out(v.ambient.size());
  v.manifold->Plus(v.ambient.data(), delta.data(), out.data());
  return out;
}

Eigen::VectorXd Values::minus(Key key, const Values& other) const {
  const Variable& v = at(key);
  const Variable& o = other.at(key);
  if (!v.manifold) return v.ambient - o.ambient;
  Eigen::VectorXd out(v.manifold->TangentSize());
  v.manifold->Minus(v.ambient.data(), o.ambient.data(), out.data());
  return out;
}

Eigen::MatrixXd Values::liftJacobian(Key key) const {
  const Variable& v = at(key);
  const int n = static_cast<int>(v.ambient.size());
  if (!v.manifold) return Eigen::MatrixXd::Identity(n, n);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(
      v.manifold->TangentSize(), n);
  v.manifold->MinusJacobian(v.ambient.data(), J.data());
  return J;
}

}  // namespace hdvio
