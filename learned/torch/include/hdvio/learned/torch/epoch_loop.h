#pragma once
// The epoch loop both TCN trainers share: run an epoch, keep the weights of the best validation
// loss (best.tcn in the checkpoint folder), stop on patience or the time budget. What an epoch
// does (loss, batches, logged columns) stays with each trainer.
#include <functional>
#include <ostream>
#include <string>

#include "hdvio/learned/tcn.h"
#include "hdvio/learned/torch/tcn_module.h"

namespace hdvio::learned {

struct EpochLoopOptions {
  int max_epochs = 0;          // epochs after epoch 0 (the untrained weights)
  int patience = 0;            // epochs without validation improvement before stopping
  double max_minutes = 0.0;    // wall-clock budget; stops after the epoch that exceeds it
  std::string checkpoint_dir;  // "" = none; else best.tcn at each improvement
  bool save_module = false;    // also checkpoint.pt (the torch module) after every epoch
  bool keep_last = false;      // a fixed epoch count: the last epoch counts as best, no patience
};

struct EpochLoopResult {
  int best_epoch = 0;
  Tcn best;  // weights of the best validation epoch
};

// Where a resumed run picks up: the next epoch to run and the best so far.
struct EpochLoopStart {
  int epoch = 0;
  double best_loss = 0.0;
  EpochLoopResult best;
};

// run_epoch(epoch, log) trains when epoch > 0, validates, logs its own columns (without a line
// end) and returns the validation loss. The loop appends " *" on improvement and the line end.
// end_of_epoch (optional) sees each finished epoch with the best so far (a resumable checkpoint).
// start (optional): continue a run instead of beginning at epoch 0.
using EpochEnd = std::function<void(int epoch, const EpochLoopResult& best, double best_loss)>;
EpochLoopResult runEpochLoop(const EpochLoopOptions& options, TcnModule& module,
                             const std::function<double(int epoch, std::ostream& log)>& run_epoch,
                             std::ostream& log, const EpochEnd& end_of_epoch = nullptr,
                             const EpochLoopStart* start = nullptr);

}  // namespace hdvio::learned
