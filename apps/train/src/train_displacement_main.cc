// hdvio_train_displacement: trains the IMO (thrust + gyro) or TLIO-style (accelerometer +
// gyro) displacement network with libtorch and writes a version-2 weight file (version 4 for
// the release architecture; task displacement, output_sigma = per-axis RMSE on the held-out
// blocks or flights). With data.validation flights the epoch is chosen on them (as the IMO
// release does on `val`). With data.cross_validation_folds, --fold k trains fold k (early
// stopping on its held-out flights, history.csv and epoch checkpoints for scripts/imo_cv_select.py) and
// --epochs N --output_sigma x,y,z the final network on the whole flights. --benchmark_batches
// measures training throughput.
// docs/imo_network.md.
#include <array>
#include <cstdio>
#include <iomanip>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <iostream>
#include <sstream>

#include <gflags/gflags.h>
#include <yaml-cpp/yaml.h>

#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/learned/tcn_weight_file.h"
#include "hdvio/learned/torch/displacement_trainer.h"
#include "hdvio/learned/torch/reproducible_kernels.h"
#include "hdvio/train/flight_loading.h"
#include "hdvio/train/training_config.h"

DEFINE_string(config, "", "training YAML (config/learned/imo_*.yaml, tlio_*.yaml)");
DEFINE_string(out, "", "output weight file (.tcn)");
DEFINE_string(data_root, "../shared/data", "prefix for relative data paths of the config");
DEFINE_string(checkpoint_dir, "", "optional folder for best.tcn (each improvement), history.csv and effective.yaml");
DEFINE_int32(fold, -1, "cross-validation fold to train (needs data.cross_validation_folds); -1 = none");
DEFINE_int32(epochs, 0, "> 0: train exactly this many epochs on all of data.train (no held-out blocks) "
             "and keep the last weights; needs --output_sigma");
DEFINE_string(output_sigma, "", "x,y,z [m] written as output_sigma with --epochs (e.g. the validation RMSE of a selection run)");
DEFINE_int32(seed, -1, ">= 0: replaces training.seed (the members of an ensemble differ only in it)");
DEFINE_int32(save_every, 0, "> 0: also write epoch_<e>.tcn every this many epochs into --checkpoint_dir");
DEFINE_bool(resume, false, "continue the training in --checkpoint_dir after its last finished epoch "
            "(resume.pt; the same --config): the weights of an uninterrupted run");
DEFINE_int32(benchmark_batches, 0, "> 0: print training windows per second (1 and 2 threads) of this "
             "many batches instead of training (--out is not written)");

namespace {

using namespace hdvio;

learned::TcnArchitecture readModel(const ConfigReader& m, std::string* inputs) {
  learned::TcnArchitecture a;
  a.residual = true;
  m.readChoice("inputs", inputs, {"thrust_gyro", "accel_gyro"}, true);
  train::readTcnShape(m, &a);
  m.readOptional("block_relu", &a.block_relu);          // the IMO release's ReLU after each block
  m.readOptional("window_padding", &a.window_padding);  // receptive field may exceed the window
  m.finish();
  train::validateTcnShape(m, a);
  return a;
}

learned::DisplacementTrainOptions readTraining(const ConfigReader& t) {
  learned::DisplacementTrainOptions o;
  train::readOptimizationKeys(t, &o);
  std::string loss = "mse", perturbation = "gaussian";
  t.readChoice("loss", &loss, {"mse", "huber"});
  o.loss = loss == "huber" ? learned::DisplacementLoss::kHuber : learned::DisplacementLoss::kMse;
  t.readInRange("huber_delta", &o.huber_delta, 1e-6, 100.0);
  t.readChoice("orientation_perturbation", &perturbation, {"gaussian", "uniform_angle"});
  o.orientation_perturbation = perturbation == "uniform_angle" ? learned::OrientationPerturbation::kUniformAngle
                                                               : learned::OrientationPerturbation::kGaussian;
  t.readInRange("orientation_sigma_deg", &o.orientation_sigma_deg, 0.0, 45.0);
  t.readInRange("gyro_bias_range", &o.gyro_bias_range, 0.0, 1.0);
  t.readInRange("accel_bias_range", &o.accel_bias_range, 0.0, 10.0);
  t.finish();
  return o;
}

int run() {
  if (FLAGS_config.empty()) throw InputError("", 0, "--config is required (see --help)");
  // A throughput measurement writes no network, so only a training needs --out.
  if (FLAGS_out.empty() && FLAGS_benchmark_batches <= 0)
    throw InputError("", 0, "--out is required (see --help)");
  const ConfigReader config = ConfigReader::fromFile(FLAGS_config);
  const ConfigReader data = config.section("data");
  std::vector<std::string> train_paths, validation_paths;
  data.read("train", &train_paths);
  // Validation flights (the release's `val`): the epoch is chosen on them, all of train trains.
  data.readOptional("validation", &validation_paths);
  double block_seconds = 5.0, thrust_coefficient = 0.0, mass = 0.0;
  int validation_every = 6, folds = 0;
  data.readInRange("validation_block_seconds", &block_seconds, 0.5, 1000.0);
  data.readInRange("validation_every", &validation_every, 2, 1000);
  // Fold k tests on the training flights at list positions i % folds == k; 0: interleaved blocks.
  data.readInRange("cross_validation_folds", &folds, 0, 100);
  data.readInRange("thrust_coefficient", &thrust_coefficient, 0.0, 1.0);
  data.readInRange("mass", &mass, 0.0, 1000.0);
  data.finish();
  std::string inputs;
  const learned::TcnArchitecture arch = readModel(config.section("model"), &inputs);
  const ConfigReader training = config.section("training");
  learned::DisplacementTrainOptions options = readTraining(training);
  if (FLAGS_seed >= 0) {
    options.seed = FLAGS_seed;
    training.recordEffective("seed", FLAGS_seed);
  }
  std::string encoding = "float32";
  config.optionalSection("output").readChoice("encoding", &encoding, {"float32", "text"});
  config.finish();
  if (train_paths.empty()) throw InputError(FLAGS_config, 0, "data.train lists no flights");
  if (FLAGS_fold >= 0 && (folds < 2 || FLAGS_fold >= folds))
    throw InputError(FLAGS_config, 0, "--fold " + std::to_string(FLAGS_fold) + " needs data.cross_validation_folds > it");
  if (FLAGS_fold >= 0 && FLAGS_epochs > 0) throw InputError("", 0, "--fold and --epochs exclude each other");
  if (!validation_paths.empty() && (FLAGS_fold >= 0 || FLAGS_epochs > 0 || folds > 0))
    throw InputError(FLAGS_config, 0, "data.validation excludes --fold, --epochs and data.cross_validation_folds");
  std::array<double, 3> fixed_sigma{};
  if (FLAGS_epochs > 0) {
    char rest = 0;
    if (std::sscanf(FLAGS_output_sigma.c_str(), "%lf,%lf,%lf%c", &fixed_sigma[0], &fixed_sigma[1],
                    &fixed_sigma[2], &rest) != 3 ||
        !(fixed_sigma[0] > 0 && fixed_sigma[1] > 0 && fixed_sigma[2] > 0))
      throw InputError("", 0, "--epochs needs --output_sigma x,y,z (three positive numbers, m)");
    options.fixed_epochs = FLAGS_epochs;
  }
  options.kind = learned::displacementInputKindFromString(inputs);
  options.checkpoint_dir = FLAGS_checkpoint_dir;
  options.resume = FLAGS_resume;
  if (FLAGS_resume) {
    const std::string state = FLAGS_checkpoint_dir + "/resume.pt", effective = FLAGS_checkpoint_dir + "/effective.yaml";
    if (FLAGS_checkpoint_dir.empty() || !std::filesystem::exists(state))
      throw InputError(state, 0, "--resume needs the resume.pt of an earlier run in --checkpoint_dir");
    // The run may be made longer (max_epochs, max_minutes); anything else must be as trained.
    const auto recipe = [](YAML::Node n) {
      if (n["training"]) n["training"].remove("max_epochs"), n["training"].remove("max_minutes");
      return YAML::Dump(n);
    };
    std::ifstream in(effective);
    const std::string before((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (recipe(YAML::Load(before)) != recipe(YAML::Load(config.effectiveYaml())))
      throw InputError(FLAGS_config, 0, "--resume: the config differs from the one the checkpoint was trained with (" +
                                            effective + "; only training.max_epochs and max_minutes may change)");
  } else if (!options.checkpoint_dir.empty()) {
    std::filesystem::create_directories(options.checkpoint_dir);
    std::ofstream(options.checkpoint_dir + "/effective.yaml") << config.effectiveYaml();
  }

  train::FlightSource source;
  source.data_root = FLAGS_data_root;
  source.thrust_coefficient = thrust_coefficient;
  source.mass = mass;
  source.rate_hz = arch.sample_rate_hz;
  // Held out: the data.validation flights, fold k's flights, or every validation_every-th block;
  // with --epochs nothing.
  std::vector<learned::FlightSamples> train_flights, validation_flights;
  for (std::size_t i = 0; i < train_paths.size(); ++i) {
    const std::string& p = train_paths[i];
    const learned::FlightSamples f = train::loadFlight(p, source);
    if (FLAGS_epochs > 0 || !validation_paths.empty()) {
      train_flights.push_back(f);
    } else if (FLAGS_fold >= 0) {
      const bool test = static_cast<int>(i % static_cast<std::size_t>(folds)) == FLAGS_fold;
      (test ? validation_flights : train_flights).push_back(f);
      if (test) std::cout << p << ": fold " << FLAGS_fold << " of " << folds << " tests on this flight\n";
    } else {
      train::splitIntoBlocks(f, static_cast<std::size_t>(block_seconds * arch.sample_rate_hz),
                             static_cast<std::size_t>(validation_every), &train_flights,
                             &validation_flights);
    }
    std::cout << p << ": " << f.size() << " samples (" << f.size() / arch.sample_rate_hz << " s)\n";
  }
  for (const std::string& p : validation_paths) {
    validation_flights.push_back(train::loadFlight(p, source));
    std::cout << p << ": validation, " << validation_flights.back().size() << " samples\n";
  }
  if (FLAGS_benchmark_batches > 0) {
    for (int threads : {1, 2}) {
      learned::DisplacementTrainer bench(arch, options);
      double cpu = 0.0;
      const double rate = bench.trainingWindowsPerSecond(train_flights, FLAGS_benchmark_batches, threads, &cpu);
      std::cout << "training throughput, " << threads << " thread(s): " << rate << " windows/s wall, "
                << FLAGS_benchmark_batches * options.batch_size / cpu << " windows per CPU second (batch "
                << options.batch_size << ", " << FLAGS_benchmark_batches << " batches)\n";
    }
    return 0;
  }
  if (FLAGS_save_every > 0 && options.checkpoint_dir.empty())
    throw InputError("", 0, "--save_every needs --checkpoint_dir");
  options.save_every = FLAGS_save_every;

  learned::DisplacementTrainer trainer(arch, options);
  const learned::DisplacementTrainingResult result = trainer.train(train_flights, validation_flights, std::cout);
  const auto& first = result.history.front();
  const auto& best = result.history[result.best_epoch];
  const Eigen::Vector3d& s = result.validation_rmse;
  std::cout << "best epoch " << result.best_epoch << " of " << result.history.size() - 1
            << ": validation MSE " << first.validation_loss << " -> " << best.validation_loss
            << " m^2, RMSE per axis " << s.transpose() << " m\n";
  if (!options.checkpoint_dir.empty()) {
    std::ofstream h(options.checkpoint_dir + "/history.csv");
    h << "epoch,train_loss,validation_mse,validation_mse_x,validation_mse_y,validation_mse_z,seconds\n";
    h << std::setprecision(9);
    for (const auto& e : result.history)
      h << e.epoch << ',' << e.train_loss << ',' << e.validation_loss << ',' << e.validation_axis_mse.x() << ','
        << e.validation_axis_mse.y() << ',' << e.validation_axis_mse.z() << ',' << e.seconds << '\n';
  }
  learned::TcnFileInfo info;
  info.task = "displacement";
  info.inputs = inputs;
  info.output_sigma = FLAGS_epochs > 0 ? std::vector<double>{fixed_sigma[0], fixed_sigma[1], fixed_sigma[2]}
                                       : std::vector<double>{s.x(), s.y(), s.z()};
  const std::string how =
      FLAGS_epochs > 0
          ? "\n" + std::to_string(FLAGS_epochs) + " epochs on all of data.train (--epochs), output_sigma " +
                FLAGS_output_sigma + " (--output_sigma)"
          : "\nbest epoch " + std::to_string(result.best_epoch) + " of " +
                std::to_string(result.history.size() - 1) + ", validation MSE " +
                std::to_string(best.validation_loss) + " m^2";
  const std::string seed = FLAGS_seed >= 0 ? " --seed " + std::to_string(FLAGS_seed) : "";
  learned::saveTcnFile(result.best, info, FLAGS_out,
                       "trained by hdvio_train_displacement --config " + FLAGS_config + seed + how,
                       encoding == "text" ? learned::TcnEncoding::kText : learned::TcnEncoding::kFloat32);
  std::cout << "wrote " << FLAGS_out << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  hdvio::learned::pinReproducibleCpuKernels();  // the same weights on every machine
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_train_displacement --config <train.yaml> --out <weights.tcn>\n"
      "       hdvio_train_displacement --config <train.yaml> --benchmark_batches <n>\n"
      "trains the IMO / TLIO-style displacement network (libtorch)\n"
      "example: hdvio_train_displacement --config config/learned/imo_blackbird.yaml --out imo.tcn");
  return runTool(run);
}
