#include "hdvio/learned/torch/epoch_loop.h"

#include <chrono>
#include <limits>

#include "hdvio/learned/tcn_weight_file.h"

namespace hdvio::learned {

EpochLoopResult runEpochLoop(const EpochLoopOptions& options, TcnModule& module,
                             const std::function<double(int epoch, std::ostream& log)>& run_epoch,
                             std::ostream& log, const EpochEnd& end_of_epoch, const EpochLoopStart* start) {
  using Clock = std::chrono::steady_clock;
  EpochLoopResult result = start ? start->best : EpochLoopResult{0, exportTcn(module)};
  double best = start ? start->best_loss : std::numeric_limits<double>::infinity();
  const auto t_start = Clock::now();
  for (int epoch = start ? start->epoch : 0; epoch <= options.max_epochs; ++epoch) {
    const double validation_loss = run_epoch(epoch, log);
    if (validation_loss < best || options.keep_last) {
      best = validation_loss;
      result.best_epoch = epoch;
      result.best = exportTcn(module);
      if (!options.checkpoint_dir.empty())
        saveTcnWeights(result.best, options.checkpoint_dir + "/best.tcn",
                       "best epoch " + std::to_string(epoch));
      if (!options.keep_last) log << "  *";
    }
    log << std::endl;
    if (end_of_epoch) end_of_epoch(epoch, result, best);
    if (options.save_module && !options.checkpoint_dir.empty())
      torch::save(module, options.checkpoint_dir + "/checkpoint.pt");
    if (epoch - result.best_epoch >= options.patience) {
      log << "early stop: no validation improvement for " << options.patience << " epochs\n";
      break;
    }
    if (std::chrono::duration<double>(Clock::now() - t_start).count() > 60.0 * options.max_minutes) {
      log << "stop: time budget of " << options.max_minutes << " min used\n";
      break;
    }
  }
  return result;
}

}  // namespace hdvio::learned
