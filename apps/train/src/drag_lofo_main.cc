// hdvio_drag_lofo: leave-one-flight-out cross-validation of the physics force model alone,
// thrust C_T sum(w^2) + drag law (core/drag_law.h), no libtorch. Fold i refits C_T on every
// flight but the i-th (as hdvio_train --hold_out i with data.refit_thrust_coefficient), fits the
// chosen drag terms on those flights' training blocks (every --validation_every-th block of
// --validation_block_seconds is left out, as hdvio_train does) and scores the i-th flight, which
// the fold never read: force RMSE of the thrust model, thrust + law (at the recorded velocity)
// and, for NeuroBEM, the dataset's own model. The law's uncertainty is a per-axis sigma fitted
// on the fold's training blocks (constant, or growing with speed, body rate and thrust:
// --sigma_terms, core/drag_law.h); the fold reports how many error components of the held-out
// flight fall within 1 and 2 sigma, their mean Gaussian NLL, and the dynamics factor's normalized
// residual at the recorded states over --nis_interval_s intervals (dynamics_nis.h). Last, the law, C_T and sigma
// fitted on all flights (the model to ship).
//   hdvio_drag_lofo --data_root ../shared/data --data <flights> --mass 0.772 --terms rotor,quadratic
//     --sigma_terms speed,rate,thrust
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <string>

#include <gflags/gflags.h>

#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/learned/flight_folds.h"
#include "hdvio/learned/force_metrics.h"
#include "hdvio/learned/thrust_identification.h"
#include "hdvio/train/drag_law_fit.h"
#include "hdvio/train/dynamics_nis.h"
#include "hdvio/train/flight_loading.h"
#include "hdvio/train/training_config.h"

DEFINE_string(data, "", "comma-separated flights (rotor speeds, IMU, ground truth): the folds");
DEFINE_string(data_root, "", "prefix for relative --data paths (e.g. ../shared/data)");
DEFINE_double(mass, 0.0, "kg (required): C_T for this mass, results in N");
DEFINE_string(terms, "linear,quadratic", "drag terms to fit: any of linear, rotor, quadratic, lift");
DEFINE_string(sigma_terms, "constant", "the law's sigma: constant, or with any of speed, rate, thrust");
DEFINE_double(nis_interval_s, 0.1, "interval of the dynamics-factor check on the held-out flight (0: off)");
DEFINE_double(nis_thrust_noise_density, 0.01,
              "m/s^2/sqrt(Hz): the factor's thrust white noise in that check (small: the law's sigma "
              "already holds the thrust model's error)");
DEFINE_double(validation_block_seconds, 5.0, "block length of the training flights' split");
DEFINE_int32(validation_every, 6, "every n-th block is left out of the fit (0: none)");
DEFINE_double(rate_hz, 100.0, "resampling rate");

namespace {

using namespace hdvio;

// Everything is printed at the end, so a bad flight in a later fold leaves no partial table.
std::string g_report;
void report(const char* format, ...) {
  char buf[1024];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buf, sizeof(buf), format, args);
  va_end(args);
  g_report += buf;
}

struct FittedModel {
  double thrust_coefficient = 0.0;
  DragLaw law;
  std::size_t samples = 0;
};

// C_T on the flights, then the law and its residual sigma on their training blocks.
FittedModel fitOn(const std::vector<std::string>& flights, const DragTerms& terms,
                  const DragSigmaTerms& sigma_terms) {
  train::FlightSource source;
  source.data_root = FLAGS_data_root;
  std::vector<Sequence> sequences;
  for (const auto& p : flights) sequences.push_back(train::loadSequence(p, source));
  FittedModel m;
  m.thrust_coefficient = learned::fitThrustJointly(sequences).thrustCoefficient(FLAGS_mass);
  source.thrust_coefficient = m.thrust_coefficient;
  source.mass = FLAGS_mass;
  source.rate_hz = FLAGS_rate_hz;
  std::vector<learned::FlightSamples> train_blocks, left_out;
  for (const auto& p : flights)
    train::splitIntoBlocks(train::loadFlight(p, source),
                           static_cast<std::size_t>(FLAGS_validation_block_seconds * FLAGS_rate_hz),
                           static_cast<std::size_t>(FLAGS_validation_every), &train_blocks, &left_out);
  m.law = train::fitDragLawOn(train_blocks, terms, sigma_terms);
  for (const auto& b : train_blocks) m.samples += b.size();
  return m;
}

void printLaw(const FittedModel& m) {
  const DragLaw& d = m.law;
  report("C_T %.6e N s^2 rad^-2; drag law linear [%.6g, %.6g, %.6g] 1/s, rotor [%.6g, %.6g, %.6g] 1/s, "
              "quadratic [%.6g, %.6g, %.6g] 1/m, lift %.6g 1/m; residual sigma [%.4f, %.4f, %.4f] N",
              m.thrust_coefficient, d.linear.x(), d.linear.y(), d.linear.z(), d.rotor.x(), d.rotor.y(),
              d.rotor.z(), d.quadratic.x(), d.quadratic.y(), d.quadratic.z(), d.lift, FLAGS_mass * d.sigma.x(),
              FLAGS_mass * d.sigma.y(), FLAGS_mass * d.sigma.z());
  if (d.hasVaryingSigma())
    report(" + per m/s [%.4f, %.4f, %.4f] N s/m, per rad/s [%.4f, %.4f, %.4f] N s, per m/s^2 of thrust "
                "[%.4f, %.4f, %.4f] kg", FLAGS_mass * d.sigma_speed.x(), FLAGS_mass * d.sigma_speed.y(),
                FLAGS_mass * d.sigma_speed.z(), FLAGS_mass * d.sigma_rate.x(), FLAGS_mass * d.sigma_rate.y(),
                FLAGS_mass * d.sigma_rate.z(), FLAGS_mass * d.sigma_thrust.x(), FLAGS_mass * d.sigma_thrust.y(),
                FLAGS_mass * d.sigma_thrust.z());
  report(" (%zu samples)\n", m.samples);
}

struct FoldResult {
  std::string flight;
  std::size_t samples = 0;
  learned::ForceRmse thrust, law, neurobem;
  bool has_neurobem = false;
  learned::SigmaCoverage coverage;
  train::DynamicsNis nis;
};

FoldResult scoreHeldOut(const std::string& flight, const FittedModel& m) {
  train::FlightSource source;
  source.data_root = FLAGS_data_root;
  source.thrust_coefficient = m.thrust_coefficient;
  source.mass = FLAGS_mass;
  source.rate_hz = FLAGS_rate_hz;
  const learned::FlightSamples f = train::loadFlight(flight, source);
  if (f.force.size() != f.size()) throw InputError(flight, 0, "the held-out flight has no IMU");
  FoldResult r;
  r.flight = flight;
  r.samples = f.size();
  const std::vector<Vec3> pred = train::thrustPlusLaw(f, m.law);
  r.thrust = learned::forceRmse(f.thrust, f.force, FLAGS_mass);
  r.law = learned::forceRmse(pred, f.force, FLAGS_mass);
  r.coverage = learned::sigmaCoverage(pred, train::lawSigma(f, m.law), f.force);
  if (FLAGS_nis_interval_s > 0.0) {
    ThrustNoiseParams noise;
    noise.thrust_noise_density = Vec3::Constant(FLAGS_nis_thrust_noise_density);
    r.nis = train::dynamicsNis(f, m.law, static_cast<std::size_t>(std::lround(FLAGS_nis_interval_s * FLAGS_rate_hz)),
                               noise);
  }
  r.has_neurobem = train::isNeuroBemFile(flight);
  if (r.has_neurobem)
    r.neurobem = learned::forceRmse(train::neuroBemForcesAt(flight, source, f.t, FLAGS_mass), f.force, FLAGS_mass);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_drag_lofo --data_root <dir> --data <flight>,<flight>[,...] --mass <kg> [--terms linear,rotor,quadratic] [--sigma_terms speed,rate,thrust]\n"
      "leave-one-flight-out force RMSE of thrust + drag law, and the law's sigma coverage\n"
      "example: hdvio_drag_lofo --data_root ../shared/data --data neurobem/a.csv,neurobem/b.csv --mass 0.772 --terms rotor,quadratic");
  return runTool([] {
    const std::vector<std::string> flights = train::splitList(FLAGS_data);
    if (flights.size() < 2) throw InputError("", 0, "--data needs at least two flights");
    if (!(FLAGS_mass > 0.0)) throw InputError("", 0, "--mass must be positive");
    if (!(FLAGS_validation_block_seconds * FLAGS_rate_hz >= 1.0) || FLAGS_validation_every < 0 ||
        FLAGS_validation_every == 1)
      throw InputError("", 0, "need --validation_block_seconds * --rate_hz >= 1 and --validation_every 0 or >= 2");
    if (!(FLAGS_nis_interval_s >= 0.0) || !std::isfinite(FLAGS_nis_interval_s) ||
        !(FLAGS_nis_thrust_noise_density >= 0.0) || !std::isfinite(FLAGS_nis_thrust_noise_density))
      throw InputError("", 0, "--nis_interval_s and --nis_thrust_noise_density must be finite and non-negative");
    const DragTerms terms = train::parseDragTerms(train::splitList(FLAGS_terms), "", "--terms");
    const DragSigmaTerms sigma_terms =
        train::parseDragSigmaTerms(train::splitList(FLAGS_sigma_terms), "", "--sigma_terms");
    std::vector<FoldResult> results;
    for (int i = 0; i < static_cast<int>(flights.size()); ++i) {
      const learned::FlightFold fold = learned::leaveOneFlightOut(flights, i);
      const FittedModel m = fitOn(fold.train, terms, sigma_terms);
      report("fold %d, held out %s: ", i, fold.test.c_str());
      printLaw(m);
      results.push_back(scoreHeldOut(fold.test, m));
    }
    report("\nterms %s, sigma %s: force RMSE F / F_xy / F_z [N] on the held-out flight; the law's sigma "
                "there: coverage (calibrated: 68.3 / 95.4 %%) and mean NLL per component (m/s^2)\n",
                FLAGS_terms.c_str(), FLAGS_sigma_terms.c_str());
    report("| held-out flight (samples) | thrust model | thrust + drag law (true v) | NeuroBEM (full state) "
                "| law / NeuroBEM (F) | within 1 / 2 sigma | NLL | factor NIS / dof: alpha, beta, joint |\n"
                "|---|---|---|---|---|---|---|---|\n");
    for (const FoldResult& r : results) {
      report("| %s (%zu) | %.4f / %.4f / %.4f | %.4f / %.4f / %.4f |", r.flight.c_str(), r.samples,
                  r.thrust.f, r.thrust.f_xy, r.thrust.f_z, r.law.f, r.law.f_xy, r.law.f_z);
      if (r.has_neurobem)
        report(" %.4f / %.4f / %.4f | %.2fx |", r.neurobem.f, r.neurobem.f_xy, r.neurobem.f_z,
                    r.law.f / r.neurobem.f);
      else
        report(" - | - |");
      report(" %.1f / %.1f %% | %.3f | %.2f, %.2f, %.2f |\n", 100.0 * r.coverage.within_1_sigma,
             100.0 * r.coverage.within_2_sigma, r.coverage.mean_nll, r.nis.alpha, r.nis.beta, r.nis.joint);
    }
    report("\nall flights: ");
    const FittedModel all = fitOn(flights, terms, sigma_terms);
    printLaw(all);
    const DragLaw& d = all.law;  // as hdvio_run backend keys (sigma mass-normalized, m/s^2)
    report("backend keys:\n  drag_linear: [%.9g, %.9g, %.9g]\n  drag_rotor: [%.9g, %.9g, %.9g]\n"
                "  drag_quadratic: [%.9g, %.9g, %.9g]\n  drag_lift: %.9g\n  drag_sigma: [%.9g, %.9g, %.9g]\n",
                d.linear.x(), d.linear.y(), d.linear.z(), d.rotor.x(), d.rotor.y(), d.rotor.z(), d.quadratic.x(),
                d.quadratic.y(), d.quadratic.z(), d.lift, d.sigma.x(), d.sigma.y(), d.sigma.z());
    if (d.hasVaryingSigma())
      report("  drag_sigma_speed: [%.9g, %.9g, %.9g]\n  drag_sigma_rate: [%.9g, %.9g, %.9g]\n"
                  "  drag_sigma_thrust: [%.9g, %.9g, %.9g]\n", d.sigma_speed.x(), d.sigma_speed.y(),
                  d.sigma_speed.z(), d.sigma_rate.x(), d.sigma_rate.y(), d.sigma_rate.z(), d.sigma_thrust.x(),
                  d.sigma_thrust.y(), d.sigma_thrust.z());
    report("thrust_coefficient: %.9g\n", all.thrust_coefficient);
    std::fputs(g_report.c_str(), stdout);
    return 0;
  });
}
