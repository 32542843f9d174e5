#pragma once
// Variables by key. Each variable is an ambient vector (stable storage, so Ceres can point at
// it) and, for non-Euclidean ones, its ceres::Manifold. Copies are deep: a copy of Values is a
// linearization point.
#include <map>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <ceres/manifold.h>

#include "hdvio/core/key.h"
#include "hdvio/core/lie.h"

namespace hdvio {

class Values {
 public:
  void insertPose(Key key, const Pose& pose);
  void insertVector(Key key, const Eigen::VectorXd& value);  // Euclidean
  void insert(Key key, const Eigen::VectorXd& ambient, std::shared_ptr<ceres::Manifold> manifold);
  // Overwrites an existing variable keeping its manifold.
  void update(Key key, const Eigen::VectorXd& ambient);
  void updatePose(Key key, const Pose& pose);
  void erase(Key key);
  void merge(const Values& other);  // inserts or overwrites every variable of other
  Values subset(const std::vector<Key>& keys) const;  // copies of these variables only

  bool exists(Key key) const { return vars_.count(key) > 0; }
  std::size_t size() const { return vars_.size(); }
  std::vector<Key> keys() const;

  Pose pose(Key key) const;
  Eigen::VectorXd vector(Key key) const;
  Vec3 vec3(Key key) const;

  double* data(Key key);
  const double* data(Key key) const;
  int ambientDim(Key key) const;
  int tangentDim(Key key) const;
  ceres::Manifold* manifold(Key key) const;  // nullptr for Euclidean variables

  // x (+) delta and y (-) x for one variable, through its manifold.
  Eigen::VectorXd plus(Key key, const Eigen::VectorXd& delta) const;
  Eigen::VectorXd minus(Key key, const Values& other) const;  // this[key] (-) other[key]
  // Tangent Jacobian lift d(tangent)/d(ambient) at the current value (identity if Euclidean).
  Eigen::MatrixXd liftJacobian(Key key) const;

 private:
  struct Variable {
    Eigen::VectorXd ambient;
    std::shared_ptr<ceres::Manifold> manifold;  // null: Euclidean
  };
  const Variable& at(Key key) const;
  Variable& at(Key key);
  std::map<Key, Variable> vars_;
};

}  // namespace hdvio
