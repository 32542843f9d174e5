// hdvio_run: one experiment (YAML) on one sequence (ASL folder or supported flight).
//   hdvio_run --config config/experiments/vio.yaml --dataset <folder> --out <dir>
//   hdvio_run --config ... --dataset flight.bag [--topics map.yaml] --calibration <mav0> --out <dir>
// The experiment's `method` selects a pipeline (apps/run/src/*_pipeline.cc); the config is
// checked completely before any data is read, the results are written atomically, and a
// sequence with ground truth is evaluated into <out>/evaluation/.
#include <gflags/gflags.h>
#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/io/sequence_reader.h"
#include "hdvio/run/method_pipeline.h"
#include "hdvio/run/result_writer.h"
#include "hdvio/run/run_evaluation.h"

DEFINE_string(config, "", "experiment YAML (method and the method's sections)");
DEFINE_string(dataset, "", "ASL folder or supported flight (Blackbird, DIDO, NeuroBEM, ROS bag)");
DEFINE_string(topics, "", "ROS bags: topic-map YAML (default: EuRoC topics, docs/datasets.md)");
DEFINE_string(calibration, "", "ROS bags: folder with cam0/ and imu0/sensor.yaml (an ASL mav0), or Kalibr files camchain.yaml,imu.yaml");

DEFINE_string(out, "", "output folder (created; an earlier result there is replaced)");
DEFINE_bool(evaluate, true, "evaluate against the sequence's ground truth into <out>/evaluation");
DEFINE_bool(plots, true, "with --evaluate: also write figures (needs python3 + matplotlib)");

namespace hdvio {
namespace {

int runMain() {
  // The estimator runs on one thread (results, timing and benchmarks are per thread); OpenCV's
  // parallel loops would otherwise spread the frontend over every core.
  cv::setNumThreads(1);
  if (FLAGS_config.empty() || FLAGS_dataset.empty() || FLAGS_out.empty())
    throw InputError("", 0, "usage: hdvio_run --config <yaml> --dataset <path> --out <dir>");
  run::checkOutputFolder(FLAGS_out);
  const ConfigReader cfg = ConfigReader::fromFile(FLAGS_config);
  const run::ExperimentFile file{FLAGS_config,
                                 std::filesystem::path(FLAGS_config).parent_path().string()};
  std::vector<std::string> methods = run::visualMethods();
  for (const auto& m : run::inertialMethods()) methods.push_back(m);
  std::string method;
  cfg.readChoice("method", &method, methods, true);
  const auto& visual = run::visualMethods();
  std::unique_ptr<run::MethodPipeline> pipeline =
      std::find(visual.begin(), visual.end(), method) != visual.end()
          ? run::makeVisualPipeline(method, cfg, file)
          : run::makeInertialPipeline(method, cfg, file);
  cfg.finish();

  io::ReadOptions read_options;
  read_options.bag_topics = FLAGS_topics;
  read_options.calibration = FLAGS_calibration;
  const Sequence seq = io::readSequence(FLAGS_dataset, read_options);
  std::fprintf(stderr, "hdvio_run: %s on %s (%zu IMU samples, %zu frames)\n", method.c_str(),
               seq.name.c_str(), seq.imu.size(), seq.images.size());
  run::RunResults results = pipeline->run(seq);
  results.effective_config = cfg.effectiveYaml();
  run::writeResults(results, FLAGS_out);
  for (const auto& s : results.stages)
    std::fprintf(stderr, "hdvio_run: %s %.2f s (%.2f ms per call, %d calls)\n", s.stage.c_str(),
                 s.total_s, 1e3 * s.total_s / std::max(1, s.calls), s.calls);
  std::fprintf(stderr, "hdvio_run: %zu states, results in %s\n", results.states.size(),
               FLAGS_out.c_str());
  if (FLAGS_evaluate) {
    run::RunEvaluationOptions evaluation;
    evaluation.plots = FLAGS_plots;
    evaluation.ground_truth_span = results.input_span;
    run::evaluateRun(seq, FLAGS_dataset, FLAGS_out, evaluation);
  }
  return 0;
}

}  // namespace
}  // namespace hdvio

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_run --config <experiment.yaml> --dataset <path> --out <dir>\n"
      "runs one experiment (VIO, VIMO, VID, HDVIO, IMO, ...) on one sequence; evaluates it when the\n"
      "sequence has ground truth\n"
      "example: hdvio_run --config config/experiments/vio.yaml --dataset ../shared/data/euroc/V1_01_easy_excerpt --out /tmp/vio");
  return hdvio::runTool(hdvio::runMain);
}
