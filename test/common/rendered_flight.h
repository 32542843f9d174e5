#pragma once
// A simulated flight rendered to camera images and written as an ASL dataset (images only, no
// landmark tracks) for the tests that run hdvio_run on images. Returns the dataset folder.
#include <filesystem>
#include <string>

#include "hdvio/core/config.h"
#include "hdvio/io/asl.h"
#include "hdvio/sim/simulator.h"

namespace hdvio::test {

// sim_config: relative to the source tree (e.g. config/sim/ci_images_moving.yaml); the dataset
// goes to dir/seq (dir is emptied first).
inline std::filesystem::path writeRenderedFlight(const std::string& sim_config,
                                                 const std::filesystem::path& dir) {
  std::filesystem::remove_all(dir);
  const sim::Simulator simulator(sim::loadSimConfig(
      ConfigReader::fromFile(std::string(HDVIO_SOURCE_DIR) + "/" + sim_config)));
  sim::SimulationResult flight = simulator.simulate();
  simulator.renderImages(&flight, (dir / "rendered").string());
  flight.sequence.landmark_observations.clear();  // images only
  io::writeAsl(flight.sequence, (dir / "seq").string());
  std::filesystem::remove_all(dir / "rendered");
  return dir / "seq";
}

}  // namespace hdvio::test
