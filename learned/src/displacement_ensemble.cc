#include "hdvio/learned/displacement_ensemble.h"

#include <stdexcept>
#include <utility>

namespace hdvio::learned {

DisplacementEnsemble::DisplacementEnsemble(std::vector<DisplacementModel> members)
    : members_(std::move(members)) {
  if (members_.empty()) throw std::invalid_argument("a displacement ensemble needs a member");
  const DisplacementModel& a = members_.front();
  for (std::size_t k = 1; k < members_.size(); ++k) {
    const DisplacementModel& b = members_[k];
    if (b.inputKind() != a.inputKind() || b.windowSamples() != a.windowSamples() ||
        b.sampleRateHz() != a.sampleRateHz() || b.sampleTimes() != a.sampleTimes())
      throw std::invalid_argument("ensemble member " + std::to_string(k + 1) +
                                  " reads another window than the first (input kind, window, "
                                  "sample rate or sample times differ)");
    if (b.hasCovariance() != a.hasCovariance())
      throw std::invalid_argument("ensemble member " + std::to_string(k + 1) +
                                  (b.hasCovariance() ? " has" : " has no") +
                                  " covariance, the first" + (a.hasCovariance() ? " has" : " has none"));
  }
}

DisplacementPrediction DisplacementEnsemble::predict(const MatrixXf& window,
                                                     TcnWorkspace* workspace) const {
  if (members_.size() == 1) return members_.front().predict(window, workspace);
  std::vector<DisplacementPrediction> p;
  p.reserve(members_.size());
  for (const DisplacementModel& m : members_) p.push_back(m.predict(window, workspace));
  const double k = static_cast<double>(p.size());
  DisplacementPrediction out;
  for (const DisplacementPrediction& q : p) out.displacement += q.displacement / k;
  if (!hasCovariance()) return out;
  for (const DisplacementPrediction& q : p) {
    const Eigen::Vector3d d = q.displacement - out.displacement;
    out.covariance += (q.covariance + d * d.transpose()) / k;
  }
  return out;
}

}  // namespace hdvio::learned
