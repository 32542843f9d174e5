// hdvio_force_eval: force RMSE (HDVIO Table I) of the thrust model alone, thrust + learned
// residual (Eigen inference; for a hybrid weight file also its drag law at the ground-truth
// velocity) and, for NeuroBEM files, the NeuroBEM model's own prediction,
// against the measured total force mass * specific force, in the body frame.
#include <cstdio>
#include <fstream>
#include <map>

#include <gflags/gflags.h>

#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/learned/force_metrics.h"
#include "hdvio/learned/force_model_error.h"
#include "hdvio/learned/tcn_weight_file.h"
#include "hdvio/train/flight_loading.h"

DEFINE_string(data, "", "comma-separated flights to evaluate");
DEFINE_string(data_root, "", "prefix for relative --data paths (e.g. ../shared/data)");
DEFINE_string(weights, "", "TCN weight file (empty: thrust model only)");
DEFINE_double(thrust_coefficient, 0.0, "N s^2 rad^-2 for rotor-speed datasets (see hdvio_thrust_id)");
DEFINE_double(mass, 0.0, "kg: read rotor thrust with this mass and report newtons (0: dataset mass "
                         "for reading, results in m/s^2)");
DEFINE_double(begin_fraction, 0.0, "evaluate from this fraction of each flight ...");
DEFINE_double(end_fraction, 1.0, "... up to this fraction");
DEFINE_double(rate_hz, 100.0, "resampling rate (must match the network's)");
DEFINE_string(drag_linear, "", "drag law alone (no --weights): linear coefficients x,y,z (body, 1/s)");
DEFINE_string(drag_quadratic, "", "... and quadratic coefficients x,y,z (1/m); see hdvio_train --fit_only");
DEFINE_string(drag_rotor, "", "... and rotor coefficients x,y,z (1/s at hover thrust); see hdvio_drag_lofo");
DEFINE_double(drag_lift, 0.0, "... and the translational-lift coefficient (1/m)");
DEFINE_double(sigma_scale, 1.0, "variance head: multiply its sigma by this (the training flights' "
                                "calibration factor, printed as 'sigma quantile')");
DEFINE_string(out_csv, "", "optional per-sample CSV: t, measured, thrust, tcn (mass-normalized)");

namespace {

using hdvio::Vec3;

struct Series {
  std::vector<Vec3> measured, thrust, law, tcn, neurobem;
  std::vector<Vec3> sigma;  // the variance head's per-axis standard deviation (m/s^2)
};

// "a,b,c" with non-negative numbers (flag_name for the message).
Vec3 coefficientsFlag(const std::string& value, const char* flag_name) {
  if (value.empty()) return Vec3::Zero();
  const auto parts = hdvio::train::splitList(value);
  Vec3 c;
  try {
    if (parts.size() != 3) throw std::invalid_argument("count");
    for (int i = 0; i < 3; ++i) c(i) = std::stod(parts[i]);
  } catch (const std::exception&) {
    throw hdvio::InputError("", 0, std::string("--") + flag_name + " needs three numbers x,y,z");
  }
  if (!(c.minCoeff() >= 0.0)) throw hdvio::InputError("", 0, std::string("--") + flag_name + ": negative coefficient");
  return c;
}

void printRow(const char* name, const std::vector<Vec3>& pred, const std::vector<Vec3>& meas, double mass) {
  const auto r = hdvio::learned::forceRmse(pred, meas, mass);
  std::printf("| %-28s | %8.4f | %8.4f | %8.4f |\n", name, r.f, r.f_xy, r.f_z);
}

void printCoverage(const Series& s) {
  const auto c = hdvio::learned::sigmaCoverage(s.tcn, s.sigma, s.measured);
  std::printf("variance head (sigma x %.4g): %.1f %% of %zu error components within 1 sigma, %.1f %% within "
              "2 sigma (calibrated: 68.3 / 95.4); sigma quantile 68.3 %%: %.4g\n", FLAGS_sigma_scale,
              100.0 * c.within_1_sigma, c.components, 100.0 * c.within_2_sigma,
              hdvio::learned::sigmaQuantile(s.tcn, s.sigma, s.measured, 0.683));
}

}  // namespace

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_force_eval --data_root <dir> --data <flight> [--weights m.tcn] [--thrust_coefficient C --mass m]\n"
      "force RMSE of the thrust model, thrust + TCN and NeuroBEM\n"
      "example: hdvio_force_eval --data_root ../shared/data --data neurobem/x.csv --weights m.tcn --thrust_coefficient 1.1e-6 --mass 0.772");
  if (const int bad = hdvio::checkRequiredFlags(__FILE__, {FLAGS_data})) return bad;
  return hdvio::runTool([] {
    if (!(FLAGS_begin_fraction >= 0.0 && FLAGS_begin_fraction < FLAGS_end_fraction && FLAGS_end_fraction <= 1.0)) {
      throw hdvio::InputError("", 0, "need 0 <= --begin_fraction < --end_fraction <= 1");
    }
    std::optional<hdvio::learned::Tcn> tcn;
    hdvio::DragLaw drag;  // a version-3 file's law: the model is law + TCN
    const char* model_label = "thrust + TCN residual";
    if (!FLAGS_weights.empty()) {
      hdvio::learned::TcnFile file = hdvio::learned::loadTcnFile(FLAGS_weights);
      if (file.info.task != "force")
        throw hdvio::InputError(FLAGS_weights, 0, "not a residual-force network (task '" + file.info.task + "')");
      tcn = std::move(file.tcn);
      drag = file.info.drag_law;
      if (drag.enabled()) model_label = "thrust + drag law + TCN";
      if (std::abs(tcn->architecture().sample_rate_hz - FLAGS_rate_hz) > 1e-6) {
        throw hdvio::InputError(FLAGS_weights, 0, "network rate differs from --rate_hz");
      }
    }
    if (!(FLAGS_sigma_scale > 0.0)) throw hdvio::InputError("", 0, "--sigma_scale must be positive");
    if (!FLAGS_drag_linear.empty() || !FLAGS_drag_quadratic.empty() || !FLAGS_drag_rotor.empty() ||
        FLAGS_drag_lift != 0.0) {
      if (tcn) throw hdvio::InputError(FLAGS_weights, 0, "give the drag law by --weights or by --drag_* flags, not both");
      drag.linear = coefficientsFlag(FLAGS_drag_linear, "drag_linear");
      drag.quadratic = coefficientsFlag(FLAGS_drag_quadratic, "drag_quadratic");
      drag.rotor = coefficientsFlag(FLAGS_drag_rotor, "drag_rotor");
      if (!(FLAGS_drag_lift >= 0.0)) throw hdvio::InputError("", 0, "--drag_lift: negative coefficient");
      drag.lift = FLAGS_drag_lift;
    }
    hdvio::train::FlightSource source;
    source.data_root = FLAGS_data_root;
    source.thrust_coefficient = FLAGS_thrust_coefficient;
    source.mass = FLAGS_mass;
    source.rate_hz = FLAGS_rate_hz;
    const double mass = FLAGS_mass > 0.0 ? FLAGS_mass : 1.0;
    Series all;
    std::vector<std::vector<Vec3>> errors;  // per flight: measured - best model
    bool all_neurobem = true;
    std::ofstream csv;
    if (!FLAGS_out_csv.empty()) {
      csv.open(FLAGS_out_csv);
      csv << "# t [s], measured xyz, thrust xyz, thrust+tcn xyz [m/s^2, body]\n";
    }
    for (const auto& path : hdvio::train::splitList(FLAGS_data)) {
      const hdvio::learned::FlightSamples f = hdvio::train::loadFlight(path, source);
      hdvio::learned::MatrixXf residual;
      if (tcn) {
        hdvio::learned::MatrixXf x(6, static_cast<long>(f.size()));
        for (std::size_t k = 0; k < f.size(); ++k) {
          x.col(k).head<3>() = f.thrust[k].cast<float>();
          x.col(k).tail<3>() = f.gyro[k].cast<float>();
        }
        residual = tcn->forwardSequence(x);
      }
      const bool neurobem = hdvio::train::isNeuroBemFile(path);
      all_neurobem = all_neurobem && neurobem;
      const std::vector<Vec3> nb = neurobem ? hdvio::train::neuroBemForcesAt(path, source, f.t, mass) : std::vector<Vec3>();
      const int warmup = tcn ? tcn->architecture().window - 1 : 0;
      const auto n = static_cast<double>(f.size());
      const std::size_t k0 = std::max<std::size_t>(warmup, static_cast<std::size_t>(FLAGS_begin_fraction * n));
      const std::size_t k1 = static_cast<std::size_t>(FLAGS_end_fraction * n);
      const bool variance = tcn && tcn->architecture().variance_head;
      Series s;
      for (std::size_t k = k0; k < k1; ++k) {
        s.measured.push_back(f.force[k]);
        s.thrust.push_back(f.thrust[k]);
        Vec3 r = tcn ? Vec3(residual.col(k).head<3>().cast<double>()) : Vec3::Zero();
        // The law at the recorded (ground-truth) velocity: it then uses part of the state.
        const Vec3 law = drag.force(f.q_WB[k].conjugate() * f.v_W[k], f.thrust[k].norm());
        s.law.push_back(f.thrust[k] + law);
        s.tcn.push_back(f.thrust[k] + law + r);
        if (variance)
          s.sigma.push_back(FLAGS_sigma_scale * (0.5 * residual.col(k).tail<3>().cast<double>()).array().exp());
        if (neurobem) s.neurobem.push_back(nb[k]);
        if (csv.is_open()) {
          csv << hdvio::toSeconds(f.t[k]);
          for (const Vec3* v : {&f.force[k], &f.thrust[k], static_cast<const Vec3*>(&s.tcn.back())})
            for (int i = 0; i < 3; ++i) csv << ',' << (*v)(i);
          csv << '\n';
        }
      }
      if (s.measured.empty()) throw hdvio::InputError(path, 0, "no samples in the evaluated fraction");
      std::printf("\n%s: %zu samples at %.0f Hz, fraction [%.2f, %.2f)\n", path.c_str(), s.measured.size(),
                  FLAGS_rate_hz, FLAGS_begin_fraction, FLAGS_end_fraction);
      std::printf("| %-28s | %8s | %8s | %8s |\n|---|---|---|---|\n", "model", "F", "F_xy", "F_z");
      printRow("thrust model", s.thrust, s.measured, mass);
      if (drag.enabled()) printRow("thrust + drag law (true v)", s.law, s.measured, mass);
      if (tcn) printRow(model_label, s.tcn, s.measured, mass);
      if (neurobem) printRow("NeuroBEM (full state)", s.neurobem, s.measured, mass);
      if (variance) printCoverage(s);
      // The best model's error, per flight (contiguous), for the walk the estimator would need.
      const std::vector<Vec3>& best = tcn ? s.tcn : drag.enabled() ? s.law : s.thrust;
      std::vector<Vec3> error(best.size());
      for (std::size_t k = 0; k < best.size(); ++k) error[k] = s.measured[k] - best[k];
      errors.push_back(std::move(error));
      for (std::vector<Vec3> Series::*v : {&Series::measured, &Series::thrust, &Series::law, &Series::tcn,
                                           &Series::neurobem, &Series::sigma})
        (all.*v).insert((all.*v).end(), (s.*v).begin(), (s.*v).end());
    }
    std::printf("\nall flights: %zu samples, RMSE in %s (body frame)\n", all.measured.size(),
                FLAGS_mass > 0.0 ? "N" : "m/s^2 (mass-normalized)");
    std::printf("| %-28s | %8s | %8s | %8s |\n|---|---|---|---|\n", "model", "F", "F_xy", "F_z");
    printRow("thrust model", all.thrust, all.measured, mass);
    if (drag.enabled()) printRow("thrust + drag law (true v)", all.law, all.measured, mass);
    if (tcn) printRow(model_label, all.tcn, all.measured, mass);
    if (all_neurobem) printRow("NeuroBEM (full state)", all.neurobem, all.measured, mass);
    if (!all.sigma.empty()) printCoverage(all);
    // What hdvio_train writes into a weight file (force_walk) and hdvio_run adopts as the least
    // external-force walk: a model trained on other flights may need more on these.
    std::printf("error walk of the best model above: %.4g m/s^2/sqrt(s) (mass-normalized)\n",
                hdvio::learned::modelErrorWalk(errors, FLAGS_rate_hz));
    return 0;
  });
}
