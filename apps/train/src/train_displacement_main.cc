// hdvio_train_displacement: trains the IMO (thrust + gyro) or TLIO-style (accelerometer +
// gyro) displacement network with libtorch and writes a version-2 weight file
// (task displacement, output_sigma = per-axis RMSE on the held-out blocks). docs/imo_network.md.
#include <filesystem>
#include <fstream>
#include <iostream>

#include <gflags/gflags.h>

#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/learned/tcn_weight_file.h"
#include "hdvio/learned/torch/displacement_trainer.h"
#include "hdvio/train/flight_loading.h"
#include "hdvio/train/training_config.h"

DEFINE_string(config, "", "training YAML (config/learned/imo_*.yaml, tlio_*.yaml)");
DEFINE_string(out, "", "output weight file (.tcn)");
DEFINE_string(data_root, "../shared/data", "prefix for relative data paths of the config");
DEFINE_string(checkpoint_dir, "", "optional folder for best.tcn (each improvement) and effective.yaml");

namespace {

using namespace hdvio;

learned::TcnArchitecture readModel(const ConfigReader& m, std::string* inputs) {
  learned::TcnArchitecture a;
  a.residual = true;
  m.readChoice("inputs", inputs, {"thrust_gyro", "accel_gyro"}, true);
  train::readTcnShape(m, &a);
  m.finish();
  train::validateTcnShape(m, a);
  return a;
}

learned::DisplacementTrainOptions readTraining(const ConfigReader& t) {
  learned::DisplacementTrainOptions o;
  train::readOptimizationKeys(t, &o);
  t.readInRange("orientation_sigma_deg", &o.orientation_sigma_deg, 0.0, 45.0);
  t.readInRange("gyro_bias_range", &o.gyro_bias_range, 0.0, 1.0);
  t.readInRange("accel_bias_range", &o.accel_bias_range, 0.0, 10.0);
  t.finish();
  return o;
}

int run() {
  if (FLAGS_config.empty() || FLAGS_out.empty()) {
    throw InputError("", 0, "--config and --out are required (see --help)");
  }
  const ConfigReader config = ConfigReader::fromFile(FLAGS_config);
  const ConfigReader data = config.section("data");
  std::vector<std::string> train_paths;
  data.read("train", &train_paths);
  double block_seconds = 5.0, thrust_coefficient = 0.0, mass = 0.0;
  int validation_every = 6;
  data.readInRange("validation_block_seconds", &block_seconds, 0.5, 1000.0);
  data.readInRange("validation_every", &validation_every, 2, 1000);
  data.readInRange("thrust_coefficient", &thrust_coefficient, 0.0, 1.0);
  data.readInRange("mass", &mass, 0.0, 1000.0);
  data.finish();
  std::string inputs;
  const learned::TcnArchitecture arch = readModel(config.section("model"), &inputs);
  learned::DisplacementTrainOptions options = readTraining(config.section("training"));
  std::string encoding = "float32";
  config.optionalSection("output").readChoice("encoding", &encoding, {"float32", "text"});
  config.finish();
  if (train_paths.empty()) throw InputError(FLAGS_config, 0, "data.train lists no flights");
  options.kind = learned::displacementInputKindFromString(inputs);
  options.checkpoint_dir = FLAGS_checkpoint_dir;
  if (!options.checkpoint_dir.empty()) {
    std::filesystem::create_directories(options.checkpoint_dir);
    std::ofstream(options.checkpoint_dir + "/effective.yaml") << config.effectiveYaml();
  }

  train::FlightSource source;
  source.data_root = FLAGS_data_root;
  source.thrust_coefficient = thrust_coefficient;
  source.mass = mass;
  source.rate_hz = arch.sample_rate_hz;
  // Every validation_every-th block of each flight is held out for early stopping and the
  // output sigma.
  std::vector<learned::FlightSamples> train_flights, validation_flights;
  for (const auto& p : train_paths) {
    const learned::FlightSamples f = train::loadFlight(p, source);
    train::splitIntoBlocks(f, static_cast<std::size_t>(block_seconds * arch.sample_rate_hz),
                           static_cast<std::size_t>(validation_every), &train_flights,
                           &validation_flights);
    std::cout << p << ": " << f.size() << " samples (" << f.size() / arch.sample_rate_hz << " s)\n";
  }

  learned::DisplacementTrainer trainer(arch, options);
  const learned::DisplacementTrainingResult result = trainer.train(train_flights, validation_flights, std::cout);
  const auto& first = result.history.front();
  const auto& best = result.history[result.best_epoch];
  const Eigen::Vector3d& s = result.validation_rmse;
  std::cout << "best epoch " << result.best_epoch << " of " << result.history.size() - 1
            << ": validation MSE " << first.validation_loss << " -> " << best.validation_loss
            << " m^2, RMSE per axis " << s.transpose() << " m\n";
  learned::TcnFileInfo info;
  info.task = "displacement";
  info.inputs = inputs;
  info.output_sigma = {s.x(), s.y(), s.z()};
  learned::saveTcnFile(result.best, info, FLAGS_out,
                       "trained by hdvio_train_displacement --config " + FLAGS_config + "\nbest epoch " +
                           std::to_string(result.best_epoch) + " of " +
                           std::to_string(result.history.size() - 1) + ", validation MSE " +
                           std::to_string(best.validation_loss) + " m^2",
                       encoding == "text" ? learned::TcnEncoding::kText : learned::TcnEncoding::kFloat32);
  std::cout << "wrote " << FLAGS_out << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_train_displacement --config <train.yaml> --out <weights.tcn>\n"
      "trains the IMO / TLIO-style displacement network (libtorch)\n"
      "example: hdvio_train_displacement --config config/learned/imo_blackbird.yaml --out imo.tcn");
  return runTool(run);
}
