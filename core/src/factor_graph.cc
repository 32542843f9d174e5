#include "hdvio/core/factor_graph.h"

namespace hdvio {

std::set<Key> FactorGraph::keys() const {
  std::set<Key> out;
  for (const auto& f : factors_) out.insert(f->keys().begin(), f->keys().end());
  return out;
}

double FactorGraph::error(const Values& values) const {
  double e = 0.0;
  for (const auto& f : factors_) e += f->error(values);
  return e;
}

}  // namespace hdvio
