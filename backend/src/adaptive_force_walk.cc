#include "hdvio/backend/adaptive_force_walk.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>

namespace hdvio {

AdaptiveForceWalk::AdaptiveForceWalk(const AdaptiveForceWalkOptions& options, double floor,
                                     double accel_noise_density)
    : options_(options),
      floor_(floor),
      noise_var_(accel_noise_density * accel_noise_density),
      walk_{Mat3::Identity(), Vec3::Constant(options.max), Mat3::Identity()} {
  if (!(floor > 0.0) || !(options.max >= floor) || !(options.block_s > 0.0) ||
      !(options.window_s >= options.block_s))
    throw std::invalid_argument(
        "AdaptiveForceWalk: need 0 < floor <= max and 0 < block_s <= window_s");
}

ForceWalkAxes AdaptiveForceWalk::update(const Vec3& f_W, double dt) {
  if (!f_W.allFinite() || !(dt > 0.0)) return walk_;  // no evidence: keep the estimate
  open_sum_ += f_W * dt;
  open_span_ += dt;
  if (open_span_ < options_.block_s - 1e-9) return walk_;  // sums of dt round below block_s
  blocks_.push_back({open_sum_ / open_span_, open_span_});
  open_sum_.setZero();
  open_span_ = 0.0;
  const std::size_t max_blocks =
      static_cast<std::size_t>(std::lround(options_.window_s / options_.block_s)) + 1;
  while (blocks_.size() > max_blocks) blocks_.pop_front();
  // Per axis E(db da^T) = Q (T_a + T_b) / 3 + sigma^2 (1 / T_a + 1 / T_b) I.
  Mat3 excess = Mat3::Zero();
  double span = 0.0;
  for (std::size_t k = 1; k < blocks_.size(); ++k) {
    const Block &a = blocks_[k - 1], &b = blocks_[k];
    const Vec3 d = b.mean - a.mean;
    excess += d * d.transpose();
    excess.diagonal().array() -= noise_var_ * (1.0 / a.span + 1.0 / b.span);
    span += (a.span + b.span) / 3.0;
  }
  // Until warmup_s of blocks are in, the evidence of calm air is thin: stay at max (as vio would).
  // At least two blocks (one increment) in any case.
  const std::size_t warmup_blocks = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::lround(options_.warmup_s / options_.block_s)) + 1, 2, max_blocks);
  if (blocks_.size() >= warmup_blocks && span > 0.0) {
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(excess / span);
    walk_.axes_W = eig.eigenvectors();
    for (int i = 0; i < 3; ++i)
      walk_.density(i) = std::clamp(std::sqrt(std::max(eig.eigenvalues()(i), 0.0)), floor_, options_.max);
  }
  return walk_;
}

}  // namespace hdvio
