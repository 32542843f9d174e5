#pragma once
// Adaptive random walk of the external force (hdvio): in calm air a tight walk lets the
// dynamics constrain the velocity, while gusts and jets need a loose one. The force the
// accelerometer sees beyond the model over each dynamics interval (world frame) is a noisy
// sample of the external force. Averaged over blocks of block_s, the spread of the increments
// between consecutive blocks over the last window_s, minus what the accelerometer's white noise
// explains, estimates the walk's density q (innovation-based adaptive process noise, as in
// adaptive INS filters, Mohamed & Schwarz 1999). The walk is sqrt(q) clamped to [floor, max],
// and max until warmup_s of blocks are in.
//
// Why blocks: per 50-ms interval the white noise (racing IMU: 0.13 m/s^2 per axis) hides a
// wind force that drifts by ~0.4 m/s^2 per sqrt(s); over 0.5-s means the drift dominates. For
// the means of a Wiener process with density q over adjacent spans T_a, T_b, per axis
// E(f_b - f_a)^2 = q (T_a + T_b) / 3 + sigma^2 (1 / T_a + 1 / T_b).
#include <deque>

#include "hdvio/core/lie.h"

namespace hdvio {

struct AdaptiveForceWalkOptions {
  bool enabled = false;
  double max = 5.0;        // m/s^2/sqrt(s)
  double block_s = 0.5;    // averaging span of one force sample
  double window_s = 4.0;   // block increments used for the estimate
  double warmup_s = 1.0;   // blocks needed before the first estimate (at most window_s)
};

class AdaptiveForceWalk {
 public:
  // floor: the walk with no evidence of a faster force (backend.force_random_walk);
  // accel_noise_density: m/s^2/sqrt(Hz).
  AdaptiveForceWalk(const AdaptiveForceWalkOptions& options, double floor, double accel_noise_density);

  // f_W: the interval's mean external force seen by the accelerometer (world frame, m/s^2),
  // dt: the interval's length (s). Returns the walk density for that interval.
  double update(const Vec3& f_W, double dt);

 private:
  struct Block {
    Vec3 mean;
    double span;
  };
  AdaptiveForceWalkOptions options_;
  double floor_;
  double noise_var_;  // sigma^2 per axis (density squared)
  Vec3 open_sum_ = Vec3::Zero();  // the block being filled: sum of f dt and its span
  double open_span_ = 0.0;
  std::deque<Block> blocks_;      // completed, oldest first
  double walk_;                   // the estimate after the last completed block (max at first)
};

}  // namespace hdvio
