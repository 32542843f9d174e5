#pragma once
// A fixed-lag smoother over Ceres in the shape of GTSAM's: update(new factors, new values,
// key timestamps) optimizes the window; marginalize(keys) removes variables through a Schur
// complement and leaves an ordinary MarginalizationPrior in the graph. Which keys leave is
// decided by the caller (a WindowPolicy) or, when lag_s > 0, by timestamps like GTSAM.
#include <map>
#include <set>
#include <vector>

#include "hdvio/backend/gauge_transform.h"
#include "hdvio/backend/schur_marginalization.h"
#include "hdvio/core/ceres_bridge.h"
#include "hdvio/core/time.h"

namespace hdvio {

struct SmootherOptions {
  OptimizerOptions optimizer;
  MarginalizationOptions marginalization;
  double lag_s = 0.0;  // > 0: after each update, marginalize keys older than newest - lag
  // Levenberg-Marquardt damping carried from one solve to the next: each solve starts with the
  // trust-region radius the previous one ended with (clamped to [min, max]), so a well-posed
  // window runs nearly Gauss-Newton and a poorly constrained one (hover, little parallax) keeps
  // the damping it needed. <= 0: every solve starts at optimizer.initial_trust_region_radius.
  double warm_start_min_radius = 0.0;
  double warm_start_max_radius = 0.0;
};

class SlidingWindowSmoother {
 public:
  using FactorId = std::size_t;

  struct UpdateResult {
    std::vector<FactorId> new_factor_ids;  // ids of the new factors, in order
    std::set<Key> marginalized;            // keys removed by the lag rule
    bool usable = true;                    // false if the solver failed (estimate unchanged)
    bool converged = true;                 // false if it stopped at its iteration budget
    int iterations = 0;
    double final_cost = 0.0;
    double solve_time_s = 0.0;
  };

  explicit SlidingWindowSmoother(SmootherOptions options = {}) : options_(std::move(options)) {}

  // Adds factors and variables (new_values must not contain existing keys) and optimizes.
  UpdateResult update(const FactorGraph& new_factors, const Values& new_values,
                      const std::map<Key, Timestamp>& key_timestamps = {}, bool optimize = true);
  // Re-optimizes the current window without adding anything.
  UpdateResult optimize();

  // Schur-complements the keys out of the window.
  void marginalize(const std::set<Key>& keys);
  // Drops factors without keeping their information (outlier rejection).
  void removeFactors(const std::vector<FactorId>& ids);
  // Drops variables and every factor touching them (e.g. a rejected landmark).
  void removeVariables(const std::set<Key>& keys);
  // A change of gauge: the estimate and the marginalization priors' linearization points move
  // together (gauge_transform.h).
  void changeGauge(const GaugeTransform& gauge);

  const Values& estimate() const { return values_; }
  Values& mutableEstimate() { return values_; }  // for re-initialization by the backend
  FactorGraph factors() const;
  std::vector<FactorId> factorIds() const;
  const FactorPtr& factor(FactorId id) const { return factors_.at(id); }
  bool hasFactor(FactorId id) const { return factors_.count(id) > 0; }
  const std::map<Key, Timestamp>& keyTimestamps() const { return key_times_; }
  void setConstant(const std::set<Key>& keys) { options_.optimizer.constant_keys = keys; }
  const SmootherOptions& options() const { return options_; }
  // Where the last solve's trust region ended (warm start; 0 before a solve or without it).
  double trustRegionRadius() const { return trust_region_radius_; }

 private:
  SmootherOptions options_;
  Values values_;
  std::map<FactorId, FactorPtr> factors_;
  std::map<Key, Timestamp> key_times_;
  FactorId next_id_ = 0;
  double trust_region_radius_ = 0.0;  // where the last solve ended (warm start), 0 = none yet
};

}  // namespace hdvio
