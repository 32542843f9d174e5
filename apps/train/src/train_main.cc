// hdvio_train: trains the residual-force TCN with libtorch from positions and velocities
// (HDVIO Eq. 7) and exports it in the Eigen weight format (tcn_weight_file.h).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

#include <gflags/gflags.h>
#include <yaml-cpp/yaml.h>

#include "hdvio/core/config.h"
#include "hdvio/core/drag_law.h"
#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/learned/flight_folds.h"
#include "hdvio/learned/force_model_error.h"
#include "hdvio/learned/training_envelope.h"
#include "hdvio/learned/tcn_weight_file.h"
#include "hdvio/learned/thrust_identification.h"
#include "hdvio/learned/torch/reproducible_kernels.h"
#include "hdvio/learned/torch/trainer.h"
#include "hdvio/train/drag_law_fit.h"
#include "hdvio/train/flight_loading.h"
#include "hdvio/train/training_config.h"

DEFINE_string(config, "", "training YAML (config/learned/train_*.yaml)");
DEFINE_string(out, "", "output weight file (.tcn)");
DEFINE_string(data_root, "../shared/data", "prefix for relative data paths of the config");
DEFINE_string(checkpoint_dir, "", "optional folder for checkpoint.pt and best.tcn");
DEFINE_int32(hold_out, -1, "leave-one-flight-out fold: train without data.train[i] (never read)");
DEFINE_bool(list_flights, false, "print data.train, one flight per line (the folds), and exit");
DEFINE_string(effective_config, "",
              "write the resolved config (fold flights, thrust coefficient, fitted drag law) here");
DEFINE_bool(fit_only, false,
            "refit the thrust coefficient and the drag law, write --effective_config, do not train");

namespace {

using namespace hdvio;

std::string vecString(const Vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "[%.6g, %.6g, %.6g]", v.x(), v.y(), v.z());
  return buf;
}

// model.drag_law: none | fit (optional drag_terms, drag_sigma_terms) | given (then drag_linear,
// drag_quadratic, optional drag_rotor, drag_lift, drag_sigma, drag_sigma_speed / _rate / _thrust). The law
// (core/drag_law.h) is the physics part of the hybrid model: the network learns what it leaves,
// and the weight file (version 3) carries the law to hdvio_run.
Vec3 readDragCoefficients(const ConfigReader& m, const std::string& key) {
  std::vector<double> c{0.0, 0.0, 0.0};
  m.readVector(key, &c, 3);
  for (double x : c)
    if (!(x >= 0.0)) throw InputError(m.file(), 0, "key 'model." + key + "': values must be non-negative");
  return Vec3(c[0], c[1], c[2]);
}

learned::TcnArchitecture readModel(const ConfigReader& m, DragLaw* drag, bool* fit_drag, DragTerms* terms,
                                   DragSigmaTerms* sigma_terms) {
  learned::TcnArchitecture a;
  train::readTcnShape(m, &a);
  m.readOptional("variance_head", &a.variance_head);
  std::string law = "none";
  m.readChoice("drag_law", &law, {"none", "fit", "given"});
  *fit_drag = law == "fit";
  if (law == "fit") {  // drag_terms: which of linear, rotor, quadratic, lift (default linear, quadratic)
    std::vector<std::string> t{"linear", "quadratic"};
    m.readOptional("drag_terms", &t);
    *terms = train::parseDragTerms(t, m.file(), "key 'model.drag_terms'");
    // drag_sigma_terms: what the law's sigma grows with besides a constant (speed, rate, thrust).
    std::vector<std::string> st;
    m.readOptional("drag_sigma_terms", &st);
    *sigma_terms = train::parseDragSigmaTerms(st, m.file(), "key 'model.drag_sigma_terms'");
  }
  if (law == "given") {
    drag->linear = readDragCoefficients(m, "drag_linear");
    drag->quadratic = readDragCoefficients(m, "drag_quadratic");
    drag->rotor = readDragCoefficients(m, "drag_rotor");
    m.readInRange("drag_lift", &drag->lift, 0.0, 10.0);
    drag->sigma = readDragCoefficients(m, "drag_sigma");
    drag->sigma_speed = readDragCoefficients(m, "drag_sigma_speed");
    drag->sigma_rate = readDragCoefficients(m, "drag_sigma_rate");
    drag->sigma_thrust = readDragCoefficients(m, "drag_sigma_thrust");
    if (!drag->enabled())
      throw InputError(m.file(), 0, "key 'model.drag_law': given needs a non-zero coefficient");
  }
  m.finish();
  train::validateTcnShape(m, a);
  return a;
}

learned::TrainOptions readTraining(const ConfigReader& t) {
  learned::TrainOptions o;
  train::readOptimizationKeys(t, &o);
  t.readInRange("segment_seconds", &o.segment_seconds, 0.01, 10.0);
  t.readInRange("gyro_bias_sigma", &o.gyro_bias_sigma, 0.0, 1.0);
  t.readInRange("variance_weight", &o.variance_weight, 0.0, 100.0);
  t.finish();
  return o;
}

// The config as this run used it: the fold's training flights and the thrust coefficient it
// refitted, so the run can be repeated with plain hdvio_train --config.
void writeEffectiveConfig(const std::string& path, const std::string& comment,
                          const std::vector<std::string>& train_paths,
                          std::map<std::string, std::string> estimate_of, double thrust_coefficient,
                          const DragLaw& drag) {
  YAML::Node n = YAML::LoadFile(FLAGS_config);
  n["data"]["train"] = train_paths;
  if (n["data"]["train_estimates"]) {
    std::vector<std::string> estimates;
    for (const auto& p : train_paths) estimates.push_back(estimate_of[p]);
    n["data"]["train_estimates"] = estimates;
  }
  n["data"].remove("refit_thrust_coefficient");
  n["data"]["thrust_coefficient"] = thrust_coefficient;
  if (drag.enabled()) {
    n["model"]["drag_law"] = "given";
    n["model"]["drag_linear"] = std::vector<double>{drag.linear.x(), drag.linear.y(), drag.linear.z()};
    n["model"]["drag_quadratic"] =
        std::vector<double>{drag.quadratic.x(), drag.quadratic.y(), drag.quadratic.z()};
    n["model"].remove("drag_terms");
    n["model"].remove("drag_sigma_terms");
    n["model"]["drag_rotor"] = std::vector<double>{drag.rotor.x(), drag.rotor.y(), drag.rotor.z()};
    n["model"]["drag_lift"] = drag.lift;
    n["model"]["drag_sigma"] = std::vector<double>{drag.sigma.x(), drag.sigma.y(), drag.sigma.z()};
    if (drag.hasVaryingSigma()) {
      const auto vec = [](const Vec3& v) { return std::vector<double>{v.x(), v.y(), v.z()}; };
      n["model"]["drag_sigma_speed"] = vec(drag.sigma_speed);
      n["model"]["drag_sigma_rate"] = vec(drag.sigma_rate);
      n["model"]["drag_sigma_thrust"] = vec(drag.sigma_thrust);
    }
  }
  YAML::Emitter e;
  e.SetDoublePrecision(9);
  e << n;
  std::ofstream out(path);
  out << "# " << comment << "\n" << e.c_str() << "\n";
  if (!out) throw InputError(path, 0, "cannot write the effective config");
}

}  // namespace

int main(int argc, char** argv) {
  hdvio::learned::pinReproducibleCpuKernels();  // the same weights on every machine
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_train --config <train.yaml> --out <weights.tcn>\n"
      "trains the residual-force TCN (libtorch)\n"
      "example: hdvio_train --config config/learned/train_neurobem.yaml --out neurobem.tcn");
  if (const int bad = hdvio::checkRequiredFlags(__FILE__, {FLAGS_config},
                                                 !FLAGS_out.empty() || FLAGS_list_flights || FLAGS_fit_only))
    return bad;
  // libtorch failures: one line "error: training failed: ...", exit 1, no partial weight file.
  return runTool([] {
    const ConfigReader config = ConfigReader::fromFile(FLAGS_config);
    const ConfigReader data = config.section("data");
    std::vector<std::string> train_paths, validation_paths, train_estimates, validation_estimates;
    data.read("train", &train_paths);
    data.readOptional("validation", &validation_paths);
    // Supervision from an estimate (no motion capture): one hdvio_run result folder per flight.
    data.readOptional("train_estimates", &train_estimates);
    data.readOptional("validation_estimates", &validation_estimates);
    if (FLAGS_list_flights) {
      for (const auto& p : train_paths) std::cout << p << "\n";
      return 0;
    }
    double block_seconds = 5.0, thrust_coefficient = 0.0, mass = 0.0;
    int validation_every = 0;
    double use_until = 1.0;
    bool refit_thrust = false;
    data.readOptional("refit_thrust_coefficient", &refit_thrust);
    data.readInRange("use_until", &use_until, 0.05, 1.0);
    data.readInRange("validation_block_seconds", &block_seconds, 0.5, 1000.0);
    data.readInRange("validation_every", &validation_every, 0, 1000);
    data.readInRange("thrust_coefficient", &thrust_coefficient, 0.0, 1.0);
    data.readInRange("mass", &mass, 0.0, 1000.0);
    data.finish();
    DragLaw drag;
    bool fit_drag = false;
    DragTerms drag_terms;
    DragSigmaTerms drag_sigma_terms;
    const learned::TcnArchitecture arch =
        readModel(config.section("model"), &drag, &fit_drag, &drag_terms, &drag_sigma_terms);
    learned::TrainOptions options = readTraining(config.section("training"));
    config.finish();
    if (train_paths.empty()) throw InputError(FLAGS_config, 0, "data.train lists no flights");
    const bool from_estimates = !train_estimates.empty();
    if (from_estimates && train_estimates.size() != train_paths.size())
      throw InputError(FLAGS_config, 0, "data.train_estimates needs one result folder per data.train flight");
    if (from_estimates != !validation_estimates.empty() && !validation_paths.empty())
      throw InputError(FLAGS_config, 0,
                       "data.train_estimates and data.validation_estimates go together (one supervision for all)");
    if (!validation_estimates.empty() && validation_estimates.size() != validation_paths.size())
      throw InputError(FLAGS_config, 0,
                       "data.validation_estimates needs one result folder per data.validation flight");
    std::map<std::string, std::string> estimate_of;  // flight -> its result folder ("" : ground truth)
    for (std::size_t i = 0; i < train_estimates.size(); ++i) estimate_of[train_paths[i]] = train_estimates[i];
    for (std::size_t i = 0; i < validation_estimates.size(); ++i)
      estimate_of[validation_paths[i]] = validation_estimates[i];
    if (validation_paths.empty() && validation_every < 2) {
      throw InputError(FLAGS_config, 0, "give data.validation flights or data.validation_every >= 2");
    }
    std::string fold_note = "all flights of data.train";
    if (FLAGS_hold_out >= 0) {
      try {
        const learned::FlightFold fold = learned::leaveOneFlightOut(train_paths, FLAGS_hold_out);
        train_paths = fold.train;
        fold_note = "fold " + std::to_string(FLAGS_hold_out) + ", held out: " + fold.test;
      } catch (const std::invalid_argument& e) {
        throw InputError(FLAGS_config, 0, std::string("--hold_out: ") + e.what());
      }
      std::cout << fold_note << "\n";
    }
    if (refit_thrust) {  // C_T from the (fold's) training flights only, as hdvio_thrust_id does
      if (!(mass > 0.0)) throw InputError(FLAGS_config, 0, "data.refit_thrust_coefficient needs data.mass");
      std::vector<Sequence> sequences;
      train::FlightSource raw;
      raw.data_root = FLAGS_data_root;
      for (const auto& p : train_paths) sequences.push_back(train::loadSequence(p, raw));
      thrust_coefficient = learned::fitThrustJointly(sequences, {}, 0.0, use_until).thrustCoefficient(mass);
      std::printf("thrust coefficient %.6e N s^2 rad^-2 (refit on the training flights)\n", thrust_coefficient);
    }
    options.checkpoint_dir = FLAGS_checkpoint_dir;
    if (!options.checkpoint_dir.empty()) std::filesystem::create_directories(options.checkpoint_dir);

    train::FlightSource source;
    source.data_root = FLAGS_data_root;
    source.thrust_coefficient = thrust_coefficient;
    source.mass = mass;
    source.rate_hz = arch.sample_rate_hz;
    std::vector<learned::FlightSamples> train_flights, validation_flights;
    for (const auto& p : train_paths) {
      // Only [0, use_until) of each flight is used; the rest stays unseen for testing.
      const learned::FlightSamples f =
          train::fractionOf(train::loadFlight(p, source, estimate_of[p]), 0.0, use_until);
      // Without separate validation flights, every validation_every-th block of each training
      // flight validates.
      train::splitIntoBlocks(f, static_cast<std::size_t>(block_seconds * arch.sample_rate_hz),
                             validation_paths.empty() ? static_cast<std::size_t>(validation_every) : 0,
                             &train_flights, &validation_flights);
      std::cout << p << ": " << f.size() << " samples (" << f.size() / arch.sample_rate_hz << " s)\n";
    }
    for (const auto& p : validation_paths)
      validation_flights.push_back(train::loadFlight(p, source, estimate_of[p]));

    if (fit_drag) drag = train::fitDragLawOn(train_flights, drag_terms, drag_sigma_terms);
    if (drag.enabled())
      std::cout << "drag law: linear " << vecString(drag.linear) << " quadratic "
                << vecString(drag.quadratic) << " rotor " << vecString(drag.rotor) << " lift " << drag.lift
                << " sigma " << vecString(drag.sigma)
                << (drag.hasVaryingSigma() ? " + per m/s " + vecString(drag.sigma_speed) + ", per rad/s " +
                                                 vecString(drag.sigma_rate) + ", per m/s^2 of thrust " +
                                                 vecString(drag.sigma_thrust)
                                           : std::string())
                << (fit_drag ? " (fitted on the training part)" : "") << "\n";
    options.drag = drag;
    if (!FLAGS_effective_config.empty())
      writeEffectiveConfig(FLAGS_effective_config, fold_note, train_paths, estimate_of, thrust_coefficient, drag);
    if (FLAGS_fit_only) return 0;
    learned::Trainer trainer(arch, options);
    const learned::TrainingResult result = trainer.train(train_flights, validation_flights, std::cout);
    const auto& first = result.history.front();
    const auto& best = result.history[result.best_epoch];
    std::cout << "best epoch " << result.best_epoch << ": validation loss " << first.validation_loss
              << " -> " << best.validation_loss << "\n";
    std::string comment = "trained by hdvio_train --config " + FLAGS_config +
                          "\nbest epoch " + std::to_string(result.best_epoch) +
                          ", validation loss " + std::to_string(best.validation_loss);
    for (const auto* paths : {&train_paths, &validation_paths})  // where the supervision came from
      for (const auto& p : *paths)
        if (!estimate_of[p].empty()) comment += "\nsupervision of " + p + ": the estimate in " + estimate_of[p];
    // What the estimator must be told about the model: how fast its error on the validation
    // part moves (learned/force_model_error.h), the least walk of the external force.
    // Flights without an accelerometer (supervision needs only positions and velocities) say
    // nothing about it; with none, the file states no walk.
    std::vector<std::vector<Vec3>> errors;
    for (const auto& f : validation_flights)
      if (f.force.size() == f.size()) errors.push_back(learned::forceModelError(f, &result.best, drag));
    const double walk = learned::modelErrorWalk(errors, arch.sample_rate_hz);
    if (errors.empty())
      std::printf("model error walk: no measured force on the validation part, none written\n");
    else
      std::printf("model error walk on the validation part: %.4g m/s^2/sqrt(s)\n", walk);
    // And where that walk holds: the speeds, rates and thrusts the training part held.
    const ModelEnvelope envelope = learned::trainingEnvelope(train_flights);
    std::printf("training envelope: speed <= %.3g m/s, rate <= %.3g rad/s, thrust %.3g-%.3g m/s^2\n",
                envelope.speed_max, envelope.rate_max, envelope.thrust_min, envelope.thrust_max);
    learned::TcnFileInfo info;  // version 7
    info.drag_law = drag;
    info.force_walk = walk;
    info.supervision = from_estimates ? "estimate" : "groundtruth";
    info.envelope = envelope;
    saveTcnFile(result.best, info, FLAGS_out, comment);
    std::cout << "wrote " << FLAGS_out << "\n";
    return 0;
  }, ToolErrorPolicy{true, "training failed: "});
}
