#include "hdvio/backend/adaptive_force_walk.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hdvio {

AdaptiveForceWalk::AdaptiveForceWalk(const AdaptiveForceWalkOptions& options, double floor,
                                     double accel_noise_density)
    : options_(options),
      floor_(floor),
      noise_var_(accel_noise_density * accel_noise_density),
      walk_(options.max) {
  if (!(floor > 0.0) || !(options.max >= floor) || !(options.block_s > 0.0) ||
      !(options.window_s >= options.block_s))
    throw std::invalid_argument(
        "AdaptiveForceWalk: need 0 < floor <= max and 0 < block_s <= window_s");
}

double AdaptiveForceWalk::update(const Vec3& f_W, double dt) {
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
  double excess = 0.0, span = 0.0;
  for (std::size_t k = 1; k < blocks_.size(); ++k) {
    const Block &a = blocks_[k - 1], &b = blocks_[k];
    excess += (b.mean - a.mean).squaredNorm() - 3.0 * noise_var_ * (1.0 / a.span + 1.0 / b.span);
    span += a.span + b.span;  // the q coefficient summed over the three axes
  }
  // Until warmup_s of blocks are in, the evidence of calm air is thin: stay at max (as vio would).
  // At least two blocks (one increment) in any case.
  const std::size_t warmup_blocks = std::clamp<std::size_t>(
      static_cast<std::size_t>(std::lround(options_.warmup_s / options_.block_s)) + 1, 2, max_blocks);
  if (blocks_.size() >= warmup_blocks && span > 0.0)
    walk_ = std::clamp(std::sqrt(std::max(excess / span, 0.0)), floor_, options_.max);
  return walk_;
}

}  // namespace hdvio
