#pragma once
// An ordered collection of factors. Factors are shared and immutable, so graphs are cheap to
// copy and a smoother can hand the same factor to several problems.
#include <set>
#include <vector>

#include "hdvio/core/factor.h"

namespace hdvio {

class FactorGraph {
 public:
  void add(FactorPtr factor) { factors_.push_back(std::move(factor)); }
  void add(const FactorGraph& other) {
    factors_.insert(factors_.end(), other.factors_.begin(), other.factors_.end());
  }
  std::size_t size() const { return factors_.size(); }
  bool empty() const { return factors_.empty(); }
  const FactorPtr& operator[](std::size_t i) const { return factors_[i]; }
  auto begin() const { return factors_.begin(); }
  auto end() const { return factors_.end(); }
  void clear() { factors_.clear(); }

  std::set<Key> keys() const;
  double error(const Values& values) const;  // sum of 0.5 |whitened residual|^2

 private:
  std::vector<FactorPtr> factors_;
};

}  // namespace hdvio
