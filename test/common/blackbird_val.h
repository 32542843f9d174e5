#pragma once
// The Blackbird validation flight the inertial tests run on (read once per test binary) and
// the position RMSE against its ground truth (no alignment).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "hdvio/core/sequence.h"
#include "hdvio/io/sequence_reader.h"

namespace hdvio::test {

inline const std::string kBlackbirdVal =
    std::string(HDVIO_DATA_DIR) + "/blackbird/clover_yawForward_maxSpeed5p0/val";

inline const Sequence& blackbirdVal() {
  static const Sequence seq = io::readSequence(kBlackbirdVal);
  return seq;
}

inline double positionRmse(const Sequence& seq, const std::vector<NavState>& states, double* max_err) {
  double sum_sq = 0.0;
  *max_err = 0.0;
  for (const NavState& s : states) {
    const double e = (s.T_WB.p - groundTruthState(seq, s.t).T_WB.p).norm();
    sum_sq += e * e;
    *max_err = std::max(*max_err, e);
  }
  return std::sqrt(sum_sq / states.size());
}

}  // namespace hdvio::test
