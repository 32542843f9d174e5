#pragma once
// Trains the residual-force TCN from positions and velocities only (HDVIO Eq. 7): over a
// segment [t_i, t_j] of ground truth, thrust plus the network's force, rotated by the
// ground-truth attitude, is preintegrated to alpha (position) and beta (velocity) and
// compared with R_i^T (p_j - p_i - v_i dt - g dt^2 / 2) and R_i^T (v_j - v_i - g dt).
// No force labels are used, so motion capture or SLAM trajectories suffice.
#include <ostream>
#include <string>
#include <vector>

#include "hdvio/core/drag_law.h"
#include "hdvio/learned/flight_samples.h"
#include "hdvio/learned/tcn.h"
#include "hdvio/learned/torch/tcn_module.h"

namespace hdvio::learned {

struct TrainOptions {
  double segment_seconds = 0.25;  // t_j - t_i
  int stride_samples = 5;         // spacing of segment starts
  int batch_size = 64;
  double learning_rate = 1e-4;    // Adam
  int max_epochs = 30;
  int patience = 5;               // epochs without validation improvement before stopping
  double gyro_bias_sigma = 1e-3;  // rad/s, augmentation: constant gyro offset per segment
  int seed = 7;
  int threads = 1;
  double max_minutes = 10.0;      // wall-clock budget; stops after the epoch that exceeds it
  double variance_weight = 0.1;   // weight of the beta NLL term (variance head only)
  std::string checkpoint_dir;     // "" = no checkpoints; else checkpoint.pt + best.tcn
  DragLaw drag;                   // physics part; the network learns the rest (none by default)
};

struct EpochStats {
  int epoch = 0;
  double train_loss = 0.0;        // mean normalized loss (m/s^2)^2
  double validation_loss = 0.0;
  double validation_beta_rms = 0.0;   // RMS of (beta error / dt), m/s^2
  double validation_alpha_rms = 0.0;  // RMS of (alpha error / (dt^2 / 2)), m/s^2
  double seconds = 0.0;
};

struct TrainingResult {
  std::vector<EpochStats> history;  // epoch 0 = before training
  int best_epoch = 0;
  Tcn best;                         // weights of the best validation epoch
};

// Segments of one flight set as tensors, with the thrust part of alpha/beta already removed
// from the targets (the network only has to explain the rest).
struct SegmentSet {
  torch::Tensor inputs;       // N x 6 x (L + window), thrust and gyro
  torch::Tensor rotations;    // N x (L + 1) x 3 x 3, R_i^T R_k
  torch::Tensor alpha_rest;   // N x 3: alpha_gt - alpha(thrust)
  torch::Tensor beta_rest;    // N x 3
  double dt = 0.0;            // sample period
  int length = 0;             // L
  int64_t size() const { return inputs.defined() ? inputs.size(0) : 0; }
};

SegmentSet buildSegments(const std::vector<FlightSamples>& flights, int window,
                         const TrainOptions& options);

class Trainer {
 public:
  Trainer(TcnArchitecture architecture, TrainOptions options);

  // Normalization statistics come from the training flights. Logs one line per epoch.
  TrainingResult train(const std::vector<FlightSamples>& train_flights,
                       const std::vector<FlightSamples>& validation_flights, std::ostream& log);

  TcnModule& module() { return module_; }

 private:
  // Returns {loss, alpha rms, beta rms} of one pass; trains when optimizer is given.
  std::vector<double> pass(const SegmentSet& set, torch::optim::Adam* optimizer);

  TcnArchitecture arch_;
  TrainOptions options_;
  TcnModule module_;
};

}  // namespace hdvio::learned
