// hdvio_displacement_eval: displacement RMSE (m, world frame, per axis and norm) of learned
// displacement networks over 0.5-s windows of evaluation flights, against two references:
// zero displacement, and integrating R * thrust + g (or R * specific force + g) from the
// ground-truth velocity at the window start. Inputs use the ground-truth attitude and the
// ground-truth biases when the dataset has them. docs/imo_network.md.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include <gflags/gflags.h>

#include "hdvio/core/error.h"
#include "hdvio/core/tool_flags.h"
#include "hdvio/core/tool_main.h"
#include "hdvio/learned/displacement_examples.h"
#include "hdvio/learned/displacement_model.h"
#include "hdvio/train/flight_loading.h"

DEFINE_string(data, "", "comma-separated evaluation flights");
DEFINE_string(data_root, "", "prefix for relative --data paths (e.g. ../shared/data)");
DEFINE_string(weights, "", "comma-separated name=file.tcn displacement networks");
DEFINE_double(thrust_coefficient, 0.0, "N s^2 rad^-2 (or C_T/m with --mass 1) for rotor-speed datasets");
DEFINE_double(mass, 0.0, "kg for rotor-speed datasets (0: the dataset's)");
DEFINE_int32(stride, 5, "samples between window ends (100 Hz)");
DEFINE_string(out, "", "optional markdown file with the tables (written atomically)");

namespace {

using namespace hdvio;
using namespace hdvio::learned;

struct Accumulator {
  Eigen::Vector3d sq = Eigen::Vector3d::Zero();
  double norm_sq = 0.0;
  std::size_t n = 0;
  void add(const Vec3& e) {
    sq += e.cwiseAbs2();
    norm_sq += e.squaredNorm();
    ++n;
  }
  void add(const Accumulator& o) {
    sq += o.sq;
    norm_sq += o.norm_sq;
    n += o.n;
  }
  std::string row(const std::string& name) const {
    char buf[256];
    const Eigen::Vector3d r = (sq / std::max<std::size_t>(n, 1)).cwiseSqrt();
    std::snprintf(buf, sizeof(buf), "| %-34s | %7.4f | %7.4f | %7.4f | %7.4f |\n", name.c_str(), r.x(), r.y(),
                  r.z(), std::sqrt(norm_sq / std::max<std::size_t>(n, 1)));
    return buf;
  }
};

Quat attitudeAt(const std::vector<GroundTruthState>& gt, Timestamp t) {
  const auto hi = std::lower_bound(gt.begin(), gt.end(), t, [](const auto& a, Timestamp v) { return a.t < v; });
  if (hi == gt.begin()) return hi->T_WB.q;
  if (hi == gt.end()) return gt.back().T_WB.q;
  const auto lo = hi - 1;
  const double f = static_cast<double>(t - lo->t) / static_cast<double>(hi->t - lo->t);
  return lo->T_WB.q.slerp(f, hi->T_WB.q).normalized();
}

template <class Get>
Vec3 gtAt(const std::vector<GroundTruthState>& gt, Timestamp t, Get get) {
  const auto hi = std::lower_bound(gt.begin(), gt.end(), t, [](const auto& a, Timestamp v) { return a.t < v; });
  if (hi == gt.begin()) return get(*hi);
  if (hi == gt.end()) return get(gt.back());
  const auto lo = hi - 1;
  const double f = static_cast<double>(t - lo->t) / static_cast<double>(hi->t - lo->t);
  return (1.0 - f) * get(*lo) + f * get(*hi);
}

int run() {
  if (FLAGS_data.empty() || FLAGS_weights.empty()) throw InputError("", 0, "--data and --weights are required");
  if (FLAGS_stride < 1) throw InputError("", 0, "--stride must be positive");
  std::vector<std::pair<std::string, DisplacementModel>> models;
  for (const auto& item : train::splitList(FLAGS_weights)) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("", 0, "--weights wants name=file, got '" + item + "'");
    models.emplace_back(item.substr(0, eq), DisplacementModel::load(item.substr(eq + 1)));
    const DisplacementModel& m = models.back().second;
    if (std::abs(m.sampleRateHz() - 100.0) > 1e-9 || m.windowSamples() != models.front().second.windowSamples()) {
      throw InputError(item.substr(eq + 1), 0, "all networks must run at 100 Hz with the same window");
    }
  }
  const int W = models.front().second.windowSamples();
  train::FlightSource source;
  source.data_root = FLAGS_data_root;
  source.thrust_coefficient = FLAGS_thrust_coefficient;
  source.mass = FLAGS_mass;
  source.rate_hz = 100.0;

  // Row order: references, then each network on resampled windows and through the filter's
  // window builder (makeDisplacementWindow on the raw streams) — the two must agree.
  std::vector<std::string> rows = {"zero displacement", "integrate thrust from GT velocity",
                                   "integrate accelerometer from GT velocity"};
  for (const auto& [name, m] : models) {
    rows.push_back(name + " (" + toString(m.inputKind()) + ")");
    rows.push_back(name + " via makeDisplacementWindow");
  }
  std::map<std::string, Accumulator> total;
  std::ostringstream md;
  md << "Displacement RMSE over " << W << "-sample windows (m, world frame), window ends every "
     << FLAGS_stride << " samples.\n\n";
  for (const auto& path : train::splitList(FLAGS_data)) {
    const Sequence seq = train::loadSequence(path, source);
    const FlightSamples f = resampleFlight(seq, {});
    const std::vector<ThrustSample> thrust = thrustSamples(seq);
    const bool biases = std::all_of(seq.groundtruth.begin(), seq.groundtruth.end(), [](const auto& g) { return g.has_biases; });
    std::map<std::string, Accumulator> acc;
    for (const auto& ex : displacementExamples({f}, W, FLAGS_stride)) {
      const Timestamp t_end = f.t[ex.end];
      if (t_end - fromSeconds(W / 100.0) < std::max(seq.imu.front().t, thrust.empty() ? 0 : thrust.front().t)) continue;
      const Vec3 target = displacementTarget(f, ex.end, W);
      acc[rows[0]].add(-target);
      acc[rows[1]].add(integratedDisplacement(f, ex.end, W, DisplacementInputKind::kThrustGyro) - target);
      acc[rows[2]].add(integratedDisplacement(f, ex.end, W, DisplacementInputKind::kAccelGyro) - target);
      const Vec3 bg = biases ? gtAt(seq.groundtruth, t_end, [](const auto& g) { return g.gyro_bias; }) : Vec3::Zero();
      const Vec3 ba = biases ? gtAt(seq.groundtruth, t_end, [](const auto& g) { return g.accel_bias; }) : Vec3::Zero();
      std::size_t r = 3;
      for (const auto& [name, m] : models) {
        acc[rows[r++]].add(m.predict(worldWindow(f, ex.end, W, m.inputKind())).displacement - target);
        const MatrixXf w = makeDisplacementWindow(
            m, seq.imu, thrust, t_end, [&](Timestamp t) { return attitudeAt(seq.groundtruth, t); }, bg, ba);
        acc[rows[r++]].add(m.predict(w).displacement - target);
      }
    }
    md << "### " << path << " (" << acc[rows[0]].n << " windows)\n\n"
       << "| model | x | y | z | norm |\n|---|---|---|---|---|\n";
    for (const auto& row : rows) {
      md << acc[row].row(row);
      total[row].add(acc[row]);
    }
    md << "\n";
  }
  md << "### all (" << total[rows[0]].n << " windows)\n\n| model | x | y | z | norm |\n|---|---|---|---|---|\n";
  for (const auto& row : rows) md << total[row].row(row);
  std::cout << md.str();
  if (!FLAGS_out.empty()) {
    const std::string tmp = FLAGS_out + ".tmp";
    {
      std::ofstream out(tmp);
      out << md.str();
      if (!out.flush()) throw InputError(FLAGS_out, 0, "cannot write");
    }
    if (std::rename(tmp.c_str(), FLAGS_out.c_str()) != 0) throw InputError(FLAGS_out, 0, "cannot move into place");
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  hdvio::parseToolFlags(&argc, &argv, __FILE__,
      "usage: hdvio_displacement_eval --data_root <dir> --data <flight>[,...] --weights name=m.tcn[,...]\n"
      "displacement RMSE of learned displacement networks vs zero and integrated references\n"
      "example: hdvio_displacement_eval --data_root ../shared/data --data blackbird/clover_yawForward_maxSpeed5p0/val --weights imo=learned/models/imo_blackbird.tcn");
  return runTool(run);
}
