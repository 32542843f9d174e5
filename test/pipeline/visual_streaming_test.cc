// The streaming example of the visual estimator: a flight fed sample by sample (IMU, thrust and
// camera images merged in time order, each image decoded when its turn comes) through the
// public VisualEstimator, as a live program would, gives the trajectory hdvio_run writes for
// the same flight and experiment, byte for byte in hdvio_run's own format: the EuRoC excerpt
// (start at rest) and a rendered flight with a moving start and thrust (vimo); no solve fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "../common/file_text.h"
#include "../common/result_text.h"
#include "../common/rendered_flight.h"
#include "../common/run_command.h"
#include "hdvio/backend/vio_options.h"
#include "hdvio/core/config.h"
#include "hdvio/io/image.h"
#include "hdvio/io/sequence_reader.h"
#include "hdvio/pipeline/visual_estimator.h"

namespace hdvio {
namespace {
namespace fs = std::filesystem;

using test::readFile;
using test::trajectoryText;
using test::velocityText;
using test::withoutHeader;

// One measurement of the merged stream; at equal times IMU and thrust come before the image
// (an image needs the IMU up to its time).
struct Event {
  Timestamp t = 0;
  int kind = 0;  // 0 IMU, 1 thrust, 2 image
  std::size_t index = 0;
};

std::vector<Event> mergedStream(const Sequence& seq, const std::vector<ThrustSample>& thrust) {
  std::vector<Event> events;
  for (std::size_t k = 0; k < seq.imu.size(); ++k) events.push_back({seq.imu[k].t, 0, k});
  for (std::size_t k = 0; k < thrust.size(); ++k) events.push_back({thrust[k].t, 1, k});
  for (std::size_t k = 0; k < seq.images.size(); ++k) events.push_back({seq.images[k].t, 2, k});
  std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
    return a.t != b.t ? a.t < b.t : a.kind < b.kind;
  });
  return events;
}

// Runs hdvio_run on the dataset with the experiment, then streams the same flight through a
// VisualEstimator with `options` (the experiment's, built by the caller) and compares.
void expectStreamingMatchesHdvioRun(const std::string& dataset, const std::string& config,
                                    const VisualEstimatorOptions& options, StartKind start) {
  const fs::path out = fs::temp_directory_path() / ("hdvio_streaming_" + std::to_string(getpid()));
  fs::remove_all(out);
  const test::CommandOutcome run = test::runCommand(std::string(HDVIO_RUN_BINARY) + " --config " +
                                                    config + " --dataset " + dataset +
                                                    " --evaluate=false --out " + out.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;

  const Sequence seq = io::readSequence(dataset);
  const std::vector<ThrustSample> thrust = thrustSamples(seq);
  VisualEstimator estimator(options, *seq.camera);
  std::vector<NavState> states;
  int images = 0;
  for (const Event& e : mergedStream(seq, thrust)) {
    if (e.kind == 0) estimator.addImu(seq.imu[e.index]);
    if (e.kind == 1) estimator.addThrust(thrust[e.index]);
    if (e.kind != 2) continue;
    ++images;
    const ImageStep step = estimator.addImage(e.t, io::loadImage(seq.images[e.index], &*seq.camera));
    if (!step.result) continue;
    // No solve fails: an observation the estimate cannot project never enters the window.
    EXPECT_TRUE(step.result->solves_usable) << "image at " << toSeconds(e.t) << " s";
    states.push_back(step.result->state);
    // The latest state the object reports is the one of this image.
    EXPECT_EQ(estimator.state().t, e.t);
  }
  EXPECT_EQ(images, static_cast<int>(seq.images.size()));
  EXPECT_GE(states.size(), seq.images.size() / 2);
  EXPECT_EQ(estimator.starter().kind(), start) << toString(estimator.starter().kind());

  const std::string written = readFile(out / "stamped_traj_estimate.txt");
  EXPECT_TRUE(written == trajectoryText(states)) << "trajectories differ";
  EXPECT_TRUE(withoutHeader(readFile(out / "stamped_velocity_estimate.csv")) == velocityText(states))
      << "velocities differ";
  fs::remove_all(out);
}

TEST(VisualStreaming, EurocExcerptSampleBySampleMatchesHdvioRunByteForByte) {
  const std::string dataset = std::string(HDVIO_DATA_DIR) + "/euroc/V1_01_easy_excerpt";
  if (!fs::exists(dataset)) GTEST_SKIP() << "no " << dataset;
  const std::string config = std::string(HDVIO_SOURCE_DIR) + "/config/experiments/vio_frontend.yaml";
  // The experiment's options: its backend section with the IMU noise of the flight's
  // calibration where it is silent (as hdvio_run); its frontend section holds the defaults.
  VisualEstimatorOptions options;
  const ConfigReader backend = ConfigReader::fromFile(config).section("backend");
  options.backend = loadVioBackendOptions(backend, VioMethod::kVio);
  adoptImuNoise(*io::readSequence(dataset).imu_calibration, backend, &options.backend);
  ASSERT_TRUE(options.frontend.backend_pose_prior && options.frontend.backend_feedback);
  expectStreamingMatchesHdvioRun(dataset, config, options, StartKind::kStaticAtRest);
}

// A moving start: the KLT tracker and the visual-inertial initialization run on the images
// before the frontend and the smoother take over (the flight of the determinism test).
TEST(VisualStreaming, RenderedMovingStartSampleBySampleMatchesHdvioRunByteForByte) {
  const fs::path dir = fs::temp_directory_path() / ("hdvio_streaming_flight_" + std::to_string(getpid()));
  const fs::path seq = test::writeRenderedFlight("config/sim/ci_images_moving.yaml", dir);
  const fs::path config = dir / "vimo_images.yaml";  // 320x240 needs a finer detector grid
  std::ofstream(config) << "method: vimo\n"
                           "frontend: {source: images, detector: {cell_size: 16}}\n";
  VisualEstimatorOptions options;
  options.backend = defaultVioBackendOptions(VioMethod::kVimo);
  adoptImuNoise(*io::readSequence(seq.string()).imu_calibration, ConfigReader::fromString("{}"),
                &options.backend);
  options.frontend.options.detector.cell_size = 16;
  expectStreamingMatchesHdvioRun(seq.string(), config.string(), options,
                                 StartKind::kVisualInertial);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hdvio
