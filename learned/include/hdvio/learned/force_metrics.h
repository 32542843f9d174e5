#pragma once
// Force errors as in HDVIO Table I: RMSE of the full force vector (F), of its body-frame xy
// part (F_xy) and of its body z component (F_z). Inputs are mass-normalized (m/s^2); `mass`
// converts to newtons (pass 1 to stay mass-normalized).
#include <vector>

#include "hdvio/core/lie.h"

namespace hdvio::learned {

struct ForceRmse {
  double f = 0.0;
  double f_xy = 0.0;
  double f_z = 0.0;
  std::size_t samples = 0;
};

// Throws std::invalid_argument if the sizes differ or are zero.
ForceRmse forceRmse(const std::vector<Vec3>& predicted, const std::vector<Vec3>& measured,
                    double mass);

// Calibration of a predicted per-axis standard deviation: the fraction of error components
// (3 per sample) with |predicted - measured| <= k * sigma, for k = 1 and 2. A calibrated
// Gaussian gives 0.683 and 0.954. mean_nll: the mean Gaussian negative log-likelihood per
// component (log sigma + z^2 / 2 + log(2 pi) / 2, sigma in the inputs' unit): lower is better,
// and it punishes a sigma too wide as well as too narrow.
struct SigmaCoverage {
  double within_1_sigma = 0.0;
  double within_2_sigma = 0.0;
  std::size_t components = 0;
  double mean_nll = 0.0;
};

// Throws std::invalid_argument if the sizes differ, are zero, or a sigma is not positive.
SigmaCoverage sigmaCoverage(const std::vector<Vec3>& predicted, const std::vector<Vec3>& sigma,
                            const std::vector<Vec3>& measured);

// The p-quantile (0 < p < 1) of |predicted - measured| / sigma over all error components: the
// factor that makes a fraction p of them fall within factor * sigma. With p = 0.683 on the
// training flights it recalibrates the variance head (sigma' = factor * sigma) without
// touching a test flight. Same preconditions as sigmaCoverage.
double sigmaQuantile(const std::vector<Vec3>& predicted, const std::vector<Vec3>& sigma,
                     const std::vector<Vec3>& measured, double p);

}  // namespace hdvio::learned
