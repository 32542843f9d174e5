#pragma once
// Several displacement networks of one recipe (trained from different seeds) used as one, as
// deep ensembles do (Lakshminarayanan et al., NeurIPS 2017): the displacement is the members'
// mean, the covariance that of their equal-weight mixture, i.e. the members' mean covariance
// plus the spread of their displacements. Where the members disagree (a manoeuvre they saw
// little of) the filter weighs the measurement less. One member is that network, unchanged.
#include <vector>

#include "hdvio/learned/displacement_model.h"

namespace hdvio::learned {

class DisplacementEnsemble {
 public:
  // Throws std::invalid_argument for no member, or members that differ in input kind, window,
  // sample rate or sample times (they must read the same window), or in whether they have a
  // covariance.
  explicit DisplacementEnsemble(std::vector<DisplacementModel> members);

  int size() const { return static_cast<int>(members_.size()); }
  // The window layout every member shares (makeDisplacementWindow takes it).
  const DisplacementModel& layout() const { return members_.front(); }
  DisplacementInputKind inputKind() const { return layout().inputKind(); }
  double windowSeconds() const { return layout().windowSeconds(); }
  Timestamp windowDuration() const { return layout().windowDuration(); }
  // Members without a covariance (the IMO release's network) leave the ensemble without one:
  // the filter then uses its own measurement sigma, and the spread is not used.
  bool hasCovariance() const { return layout().hasCovariance(); }

  // window: as DisplacementModel::predict. Mean displacement; covariance
  // (1/K) sum_k (C_k + (d_k - d)(d_k - d)^T) when the members have covariances, else zero.
  DisplacementPrediction predict(const MatrixXf& window, TcnWorkspace* workspace) const;

 private:
  std::vector<DisplacementModel> members_;
};

}  // namespace hdvio::learned
