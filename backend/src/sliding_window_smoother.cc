#include "hdvio/backend/sliding_window_smoother.h"

#include <algorithm>
#include <memory>
#include <stdexcept>

namespace hdvio {

SlidingWindowSmoother::UpdateResult SlidingWindowSmoother::update(
    const FactorGraph& new_factors, const Values& new_values,
    const std::map<Key, Timestamp>& key_timestamps, bool run_optimizer) {
  for (Key k : new_values.keys())
    if (values_.exists(k)) throw std::logic_error("smoother update: key exists: " + k.str());
  values_.merge(new_values);
  for (const auto& [k, t] : key_timestamps) key_times_[k] = t;
  UpdateResult result;
  for (const auto& f : new_factors) {
    for (Key k : f->keys())
      if (!values_.exists(k))
        throw std::logic_error("smoother update: factor refers to unknown key " + k.str());
    factors_[next_id_] = f;
    result.new_factor_ids.push_back(next_id_++);
  }
  if (run_optimizer) {
    const UpdateResult solved = optimize();
    result.usable = solved.usable;
    result.converged = solved.converged;
    result.iterations = solved.iterations;
    result.final_cost = solved.final_cost;
    result.solve_time_s = solved.solve_time_s;
  }
  if (options_.lag_s > 0.0 && !key_times_.empty()) {
    Timestamp newest = key_times_.begin()->second;
    for (const auto& kv : key_times_) newest = std::max(newest, kv.second);
    const Timestamp cutoff = newest - fromSeconds(options_.lag_s);
    for (const auto& [k, t] : key_times_)
      if (t < cutoff) result.marginalized.insert(k);
    if (!result.marginalized.empty()) marginalize(result.marginalized);
  }
  return result;
}

SlidingWindowSmoother::UpdateResult SlidingWindowSmoother::optimize() {
  UpdateResult result;
  if (factors_.empty()) return result;
  OptimizerOptions optimizer = options_.optimizer;
  const bool warm_start = options_.warm_start_min_radius > 0.0 && options_.warm_start_max_radius > 0.0;
  if (warm_start && trust_region_radius_ > 0.0) optimizer.initial_trust_region_radius = trust_region_radius_;
  // values_ change only if the solve is usable.
  const OptimizeResult solved = hdvio::optimize(factors(), &values_, optimizer);
  if (warm_start && !solved.summary.iterations.empty())
    trust_region_radius_ = std::clamp(solved.summary.iterations.back().trust_region_radius,
                                      options_.warm_start_min_radius, options_.warm_start_max_radius);
  result.usable = solved.usable;
  result.converged = solved.summary.termination_type == ceres::CONVERGENCE;
  result.iterations = static_cast<int>(solved.summary.iterations.size());
  result.final_cost = solved.summary.final_cost;
  result.solve_time_s = solved.summary.total_time_in_seconds;
  return result;
}

void SlidingWindowSmoother::marginalize(const std::set<Key>& keys) {
  if (keys.empty()) return;
  FactorGraph involved;
  std::vector<FactorId> involved_ids;
  for (const auto& [id, f] : factors_) {
    for (Key k : f->keys()) {
      if (keys.count(k)) {
        involved.add(f);
        involved_ids.push_back(id);
        break;
      }
    }
  }
  std::shared_ptr<MarginalizationPrior> prior;
  if (!involved.empty())
    prior = marginalizeBySchurComplement(involved, values_, keys, options_.marginalization);
  for (FactorId id : involved_ids) factors_.erase(id);
  for (Key k : keys) {
    values_.erase(k);
    key_times_.erase(k);
  }
  if (prior) factors_[next_id_++] = prior;
}

void SlidingWindowSmoother::removeFactors(const std::vector<FactorId>& ids) {
  for (FactorId id : ids) factors_.erase(id);
}

void SlidingWindowSmoother::removeVariables(const std::set<Key>& keys) {
  for (auto it = factors_.begin(); it != factors_.end();) {
    bool touches = false;
    for (Key k : it->second->keys()) touches = touches || keys.count(k) > 0;
    it = touches ? factors_.erase(it) : std::next(it);
  }
  for (Key k : keys) {
    values_.erase(k);
    key_times_.erase(k);
  }
}

void SlidingWindowSmoother::changeGauge(const GaugeTransform& gauge) {
  gauge.apply(&values_);
  for (auto& [id, f] : factors_) {
    const auto* prior = dynamic_cast<const MarginalizationPrior*>(f.get());
    if (!prior) continue;
    Values x0 = prior->linearizationPoint();
    gauge.apply(&x0);
    f = prior->withLinearizationPoint(x0);
  }
}

FactorGraph SlidingWindowSmoother::factors() const {
  FactorGraph g;
  for (const auto& kv : factors_) g.add(kv.second);
  return g;
}

std::vector<SlidingWindowSmoother::FactorId> SlidingWindowSmoother::factorIds() const {
  std::vector<FactorId> ids;
  for (const auto& kv : factors_) ids.push_back(kv.first);
  return ids;
}

}  // namespace hdvio
