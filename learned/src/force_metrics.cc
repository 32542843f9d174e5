#include "hdvio/learned/force_metrics.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hdvio::learned {

ForceRmse forceRmse(const std::vector<Vec3>& predicted, const std::vector<Vec3>& measured,
                    double mass) {
  if (predicted.size() != measured.size() || predicted.empty()) {
    throw std::invalid_argument("force RMSE needs two equally long, non-empty series");
  }
  double se = 0.0, se_xy = 0.0, se_z = 0.0;
  for (std::size_t k = 0; k < predicted.size(); ++k) {
    const Vec3 e = mass * (predicted[k] - measured[k]);
    se += e.squaredNorm();
    se_xy += e.head<2>().squaredNorm();
    se_z += e.z() * e.z();
  }
  const double n = static_cast<double>(predicted.size());
  return {std::sqrt(se / n), std::sqrt(se_xy / n), std::sqrt(se_z / n), predicted.size()};
}

SigmaCoverage sigmaCoverage(const std::vector<Vec3>& predicted, const std::vector<Vec3>& sigma,
                            const std::vector<Vec3>& measured) {
  if (predicted.size() != measured.size() || sigma.size() != measured.size() || predicted.empty()) {
    throw std::invalid_argument("sigma coverage needs three equally long, non-empty series");
  }
  std::size_t in1 = 0, in2 = 0;
  double nll = 0.0;
  for (std::size_t k = 0; k < predicted.size(); ++k) {
    for (int i = 0; i < 3; ++i) {
      if (!(sigma[k](i) > 0.0)) throw std::invalid_argument("sigma coverage: non-positive sigma");
      const double e = std::abs(predicted[k](i) - measured[k](i));
      in1 += e <= sigma[k](i);
      in2 += e <= 2.0 * sigma[k](i);
      const double z = e / sigma[k](i);
      nll += std::log(sigma[k](i)) + 0.5 * z * z;
    }
  }
  const double n = 3.0 * static_cast<double>(predicted.size());
  return {in1 / n, in2 / n, 3 * predicted.size(), nll / n + 0.5 * std::log(2.0 * M_PI)};
}

double sigmaQuantile(const std::vector<Vec3>& predicted, const std::vector<Vec3>& sigma,
                     const std::vector<Vec3>& measured, double p) {
  sigmaCoverage(predicted, sigma, measured);  // the same checks
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("sigma quantile: p must be in (0, 1)");
  std::vector<double> z;
  for (std::size_t k = 0; k < predicted.size(); ++k)
    for (int i = 0; i < 3; ++i) z.push_back(std::abs(predicted[k](i) - measured[k](i)) / sigma[k](i));
  const auto at = static_cast<std::size_t>(std::ceil(p * static_cast<double>(z.size()))) - 1;
  std::nth_element(z.begin(), z.begin() + at, z.end());
  return z[at];
}

}  // namespace hdvio::learned
