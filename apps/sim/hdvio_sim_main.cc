// hdvio_sim --config <yaml> --out <folder>: writes a synthetic flight as an ASL folder
// (FORMATS.md), deterministic for a given config (seed included).
#include <gflags/gflags.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>

#include <opencv2/core.hpp>

#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/io/asl.h"
#include "hdvio/sim/simulator.h"

DEFINE_string(config, "", "Simulator scenario YAML (see config/sim/)");
DEFINE_string(out, "", "Output folder (ASL layout, <out>/mav0/...)");
DEFINE_bool(overwrite, false, "Replace an existing non-empty output folder");
DEFINE_bool(no_images, false,
            "Skip rendering: cam0 keeps its calibration but lists no images (the landmark "
            "tracks the backends use are still written); for fast benchmark sequences");

namespace fs = std::filesystem;

namespace {

void run() {
  const auto start = std::chrono::steady_clock::now();
  const hdvio::ConfigReader reader = hdvio::ConfigReader::fromFile(FLAGS_config);
  const hdvio::sim::SimConfig config = hdvio::sim::loadSimConfig(reader);

  fs::path out = fs::absolute(FLAGS_out).lexically_normal();
  if (out.filename().empty()) out = out.parent_path();
  if (fs::exists(out) && !(fs::is_directory(out) && fs::is_empty(out)) && !FLAGS_overwrite)
    throw hdvio::InputError(out.string(), 0, "output folder exists and is not empty (use --overwrite)");

  const hdvio::sim::Simulator simulator(config);  // validates the whole flight before writing
  const fs::path stage = out.parent_path() / ("." + out.filename().string() + ".sim-partial-" +
                                              std::to_string(::getpid()));
  try {
    fs::remove_all(stage);
    hdvio::sim::SimulationResult result = simulator.simulate();
    if (!FLAGS_no_images)
      simulator.renderImages(&result, (stage / "mav0" / "cam0" / "data").string());
    hdvio::io::writeAsl(result.sequence, stage.string());
    if (!result.gates.corners.empty())
      hdvio::io::writeGateData(result.gates, (stage / "mav0").string());
    std::ofstream(stage / "sim_config.yaml") << reader.effectiveYaml() << "\n";
    if (fs::exists(out)) fs::remove_all(out);
    fs::rename(stage, out);

    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const hdvio::Sequence& seq = result.sequence;
    std::printf("wrote %s: %.1f s flight, %zu IMU samples, %zu images, %zu landmark observations, "
                "peak speed %.2f m/s, generated in %.1f s\n",
                out.c_str(), config.duration, seq.imu.size(), seq.images.size(),
                seq.landmark_observations.size(), simulator.model().trajectory().peakSpeed(), seconds);
    if (!result.gates.corners.empty())
      std::printf("gates: %zu corners, %zu corner detections\n", result.gates.corners.size(),
                  result.gates.detections.size());
    for (const std::string& w : seq.warnings) std::printf("warning: %s\n", w.c_str());
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(stage, ignored);
    throw;
  }
}

// Model errors (flight leaves the room, needs negative thrust, ...) carry no file: they are
// about the scenario, so name it.
void runNamingScenario() {
  try {
    run();
  } catch (const hdvio::InputError& e) {
    if (!e.file().empty()) throw;
    throw hdvio::InputError(FLAGS_config, 0, e.problem());
  }
}

}  // namespace

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_sim --config <scenario.yaml> --out <folder> [--overwrite] [--no_images]\n"
      "writes a deterministic synthetic flight as an ASL folder\n"
      "example: hdvio_sim --config config/sim/ci_tiny.yaml --out /tmp/sim_tiny");
  cv::setNumThreads(1);  // one core by design (benchmarks, shared CI machines)
  if (const int bad = hdvio::checkRequiredFlags(__FILE__, {FLAGS_config, FLAGS_out}, argc == 1)) return bad;
  return hdvio::runTool([&] {
    runNamingScenario();
    return 0;
  });
}
