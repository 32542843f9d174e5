// hdvio_run's gate_io method: bad configs and sequences without gate files are InputErrors
// (the estimator itself: test/imo/gate_io_test.cc).
#include <gtest/gtest.h>

#include <filesystem>

#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/run/method_pipeline.h"
#include "hdvio/sim/simulator.h"

namespace hdvio {
namespace {

TEST(GateIoPipeline, RejectsBadConfigsAndSequencesWithoutGates) {
  const run::ExperimentFile file{"gate_io.yaml", ""};
  auto make = [&](const std::string& yaml) {
    const ConfigReader cfg = ConfigReader::fromString(yaml, "gate_io.yaml");
    std::string method;
    cfg.read("method", &method);
    auto p = run::makeInertialPipeline(method, cfg, file);
    cfg.finish();
    return p;
  };
  EXPECT_NO_THROW(make("method: gate_io\n"));
  EXPECT_THROW(make("method: gate_io\ndisplacement: sometimes\n"), InputError);
  EXPECT_THROW(make("method: gate_io\ngate: {pixel_sigma: -1}\n"), InputError);
  EXPECT_THROW(make("method: gate_io\ngate: {pixle_sigma: 1}\n"), InputError);
  EXPECT_THROW(make("method: gate_io\nnetwork: {weights: x.tcn}\n"), InputError);
  EXPECT_THROW(make("method: gate_io\ndisplacement: network\n"), InputError);  // no network section
  // A sequence without gate files: the error names the missing file.
  const sim::Simulator simulator(sim::loadSimConfig(
      ConfigReader::fromFile(std::string(HDVIO_SOURCE_DIR) + "/config/sim/ci_race_tiny.yaml")));
  Sequence seq = simulator.simulate().sequence;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "hdvio_gate_io_nogates";
  std::filesystem::create_directories(dir);
  seq.source = dir.string();
  try {
    make("method: gate_io\n")->run(seq);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(e.file().find("gates0/gates.csv"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hdvio
