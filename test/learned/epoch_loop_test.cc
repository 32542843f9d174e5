// The trainers' shared epoch loop: best weights, patience, time budget, best.tcn.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <vector>

#include "hdvio/learned/tcn_weight_file.h"
#include "hdvio/learned/torch/epoch_loop.h"

namespace hdvio::learned {
namespace {

TcnModule tinyModule() {
  TcnArchitecture a;
  a.window = 8;
  a.layers = {{4, 1}, {4, 2}};
  return TcnModule(a);
}

// Scripted validation losses; each epoch also shifts one weight so "best" is identifiable.
struct ScriptedEpochs {
  std::vector<double> losses;
  TcnModule module;
  std::vector<int> ran;
  double operator()(int epoch, std::ostream& log) {
    ran.push_back(epoch);
    torch::NoGradGuard no_grad;
    module->head()->bias.fill_(static_cast<double>(epoch));
    log << "epoch " << epoch;
    return losses.at(static_cast<std::size_t>(epoch));
  }
};

TEST(EpochLoop, KeepsTheBestEpochAndStopsAfterPatience) {
  ScriptedEpochs s{{5.0, 3.0, 1.0, 2.0, 1.5, 1.2, 0.5, 0.1}, tinyModule(), {}};
  std::ostringstream log;
  const EpochLoopResult r = runEpochLoop({7, 3, 60.0, "", false}, s.module,
                                         [&](int e, std::ostream& o) { return s(e, o); }, log);
  EXPECT_EQ(r.best_epoch, 2) << log.str();
  EXPECT_EQ(s.ran, (std::vector<int>{0, 1, 2, 3, 4, 5})) << log.str();  // 3 epochs without gain
  // The returned weights are those of epoch 2, not the last epoch's.
  EXPECT_FLOAT_EQ(r.best.weights().head_bias(0), 2.0f);
  EXPECT_NE(log.str().find("early stop"), std::string::npos);
}

TEST(EpochLoop, RunsAllEpochsWhileImprovingAndWritesBestWeights) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "hdvio_epoch_loop_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ScriptedEpochs s{{4.0, 3.0, 2.0, 1.0}, tinyModule(), {}};
  std::ostringstream log;
  const EpochLoopResult r = runEpochLoop({3, 2, 60.0, dir.string(), false}, s.module,
                                         [&](int e, std::ostream& o) { return s(e, o); }, log);
  EXPECT_EQ(r.best_epoch, 3);
  EXPECT_EQ(s.ran.size(), 4u);
  const Tcn saved = loadTcnWeights((dir / "best.tcn").string());
  EXPECT_FLOAT_EQ(saved.weights().head_bias(0), 3.0f);
  std::filesystem::remove_all(dir);
}

TEST(EpochLoop, StopsWhenTheTimeBudgetIsUsed) {
  ScriptedEpochs s{{4.0, 3.0, 2.0, 1.0}, tinyModule(), {}};
  std::ostringstream log;
  runEpochLoop({3, 10, 0.0, "", false}, s.module, [&](int e, std::ostream& o) { return s(e, o); },
               log);
  EXPECT_EQ(s.ran.size(), 1u);  // a zero budget ends after the first epoch
  EXPECT_NE(log.str().find("time budget"), std::string::npos);
}

}  // namespace
}  // namespace hdvio::learned
