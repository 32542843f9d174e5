#pragma once
// Trains the displacement network of IMO / TLIO-style inertial odometry (displacement_model.h)
// with an MSE or Huber loss on the world-frame displacement over the window. Augmentation per
// window and epoch, as the filter will see: the ground-truth attitude that rotates the inputs
// to the world is perturbed by a small random rotation Exp(delta) R_k (constant over the
// window), and a constant gyro (and, for accelerometer inputs, accelerometer) bias error is
// added.
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "hdvio/learned/displacement_model.h"
#include "hdvio/learned/flight_samples.h"
#include "hdvio/learned/torch/tcn_module.h"

namespace hdvio::learned {

enum class DisplacementLoss {
  kMse,    // squared error summed over the axes, mean over the batch
  kHuber,  // torch's HuberLoss(delta) mean over batch and axes (the IMO release, delta 0.5 m)
};

enum class OrientationPerturbation {
  kGaussian,      // delta ~ N(0, sigma^2) per axis
  kUniformAngle,  // random axis, angle ~ U(0, sigma) (the IMO release's datasets.py)
};

struct DisplacementTrainOptions {
  DisplacementInputKind kind = DisplacementInputKind::kThrustGyro;
  int stride_samples = 5;              // spacing of window ends (0.05 s at 100 Hz)
  int batch_size = 128;
  double learning_rate = 5e-4;         // Adam
  int max_epochs = 200;
  int patience = 20;                   // epochs without validation improvement before stopping
  DisplacementLoss loss = DisplacementLoss::kMse;
  double huber_delta = 0.5;            // m
  OrientationPerturbation orientation_perturbation = OrientationPerturbation::kGaussian;
  double orientation_sigma_deg = 2.0;  // per-axis std (Gaussian) or largest angle (uniform)
  double gyro_bias_range = 0.01;       // rad/s, uniform in [-r, r] per axis
  double accel_bias_range = 0.2;       // m/s^2, accelerometer inputs only
  int seed = 7;
  int threads = 1;
  double max_minutes = 10.0;           // wall-clock budget; stops after the epoch that exceeds it
  // > 0: train exactly this many epochs and keep the last weights (no early stopping; the
  // final network after cross-validation chose the count). Validation flights may be empty.
  int fixed_epochs = 0;
  // > 0 (with checkpoint_dir): epoch_<e>.tcn every this many epochs, a displacement weight file
  // whose output_sigma is that epoch's per-axis validation RMSE (cross-validation folds).
  int save_every = 0;
  std::string checkpoint_dir;          // "" = none; else best.tcn at each improvement and
                                       // resume.pt after every epoch (weights, Adam, RNG, history)
  bool resume = false;                 // continue from checkpoint_dir/resume.pt: the same weights
                                       // as a run that was never interrupted
};

struct DisplacementEpoch {
  int epoch = 0;
  double train_loss = 0.0;       // mean squared displacement error, m^2 (augmented inputs)
  double validation_loss = 0.0;  // mean squared error on the validation windows (unperturbed inputs)
  Eigen::Vector3d validation_axis_mse = Eigen::Vector3d::Zero();  // per axis, m^2
  double seconds = 0.0;
};

struct DisplacementTrainingResult {
  std::vector<DisplacementEpoch> history;  // epoch 0 = before training
  int best_epoch = 0;
  Tcn best;                                // weights of the best validation epoch
  Eigen::Vector3d validation_rmse = Eigen::Vector3d::Zero();  // per axis, m, of `best`
};

// Windows of a flight set as tensors.
struct DisplacementSet {
  torch::Tensor inputs;     // N x 6 x W, world frame (ground-truth attitude)
  torch::Tensor rotations;  // N x W x 3 x 3, world_from_body of each sample
  torch::Tensor targets;    // N x 3, m
  int64_t size() const { return inputs.defined() ? inputs.size(0) : 0; }
};

DisplacementSet buildDisplacementSet(const std::vector<FlightSamples>& flights, int window,
                                     DisplacementInputKind kind, int stride);

class DisplacementTrainer {
 public:
  DisplacementTrainer(TcnArchitecture architecture, DisplacementTrainOptions options);

  // Normalization statistics come from the training windows. Logs one line per epoch.
  DisplacementTrainingResult train(const std::vector<FlightSamples>& train_flights,
                                   const std::vector<FlightSamples>& validation_flights,
                                   std::ostream& log);

  // Training throughput: windows per second (wall clock) of `batches` optimizer steps
  // (augmentation, forward, backward, Adam) on the flights' windows, with `threads` threads.
  // Changes the weights (a benchmark, not a training). cpu_seconds (optional): the process CPU
  // time of the timed batches (all threads).
  double trainingWindowsPerSecond(const std::vector<FlightSamples>& flights, int batches, int threads,
                                  double* cpu_seconds = nullptr);

  TcnModule& module() { return module_; }

 private:
  // Per-axis mean squared error (m^2) of one pass; trains (with augmentation) when optimizer
  // is given.
  Eigen::Vector3d pass(const DisplacementSet& set, torch::optim::Adam* optimizer);
  torch::Tensor loss(const torch::Tensor& prediction, const torch::Tensor& target) const;
  // The batch's augmented inputs (B x 6 x W) and targets (B x 3).
  std::pair<torch::Tensor, torch::Tensor> augment(const DisplacementSet& set, const torch::Tensor& idx) const;

  // resume.pt in the checkpoint folder: after `epoch`, the module, Adam, torch's CPU generator,
  // the best epoch and loss and the history; written atomically.
  void saveResumeState(int epoch, int best_epoch, double best_loss, torch::optim::Adam& optimizer,
                       const std::vector<DisplacementEpoch>& history);
  // Restores what saveResumeState wrote; returns where the loop picks up. Throws
  // std::invalid_argument when the folder has no such file.
  struct Resumed;
  Resumed loadResumeState(torch::optim::Adam& optimizer, std::vector<DisplacementEpoch>* history);

  TcnArchitecture arch_;
  DisplacementTrainOptions options_;
  TcnModule module_;
};

}  // namespace hdvio::learned
