#include "hdvio/train/estimate_supervision.h"

#include <cstdio>
#include <filesystem>

#include "hdvio/core/error.h"
#include "hdvio/eval/text_table.h"
#include "hdvio/eval/trajectory_io.h"

namespace hdvio::train {
namespace fs = std::filesystem;
namespace {

std::string seconds(Timestamp t) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.3f", toSeconds(t));
  return buf;
}

// A stamp of the CSV files (integer ns) and one of the trajectory (decimal seconds, exact to
// the ns it was written with) name the same image within a microsecond.
bool sameImage(Timestamp a, Timestamp b) { return std::abs(a - b) <= 1000; }

void requireSameStamps(const std::string& file, const std::vector<Timestamp>& t,
                       const std::vector<GroundTruthState>& states) {
  if (t.size() != states.size())
    throw InputError(file, 0, std::to_string(t.size()) + " rows for the " +
                                  std::to_string(states.size()) + " poses of stamped_traj_estimate.txt");
  for (std::size_t k = 0; k < t.size(); ++k)
    if (!sameImage(t[k], states[k].t))
      throw InputError(file, 0, "row " + std::to_string(k + 1) + " is at " + seconds(t[k]) +
                                    " s, its pose at " + seconds(states[k].t) + " s");
}

}  // namespace

std::vector<GroundTruthState> readEstimatedStates(const std::string& result_dir) {
  const fs::path dir(result_dir);
  if (!fs::is_directory(dir)) throw InputError(result_dir, 0, "no such result folder");
  const std::string traj_file = (dir / "stamped_traj_estimate.txt").string();
  const std::string vel_file = (dir / "stamped_velocity_estimate.csv").string();
  if (!fs::exists(traj_file)) throw InputError(traj_file, 0, "missing (an hdvio_run result folder?)");
  if (!fs::exists(vel_file))
    throw InputError(vel_file, 0, "missing: supervision needs the estimate's velocities");
  const eval::Trajectory traj = eval::readTumTrajectory(traj_file);
  std::vector<GroundTruthState> states(traj.size());
  for (std::size_t k = 0; k < traj.size(); ++k) {
    states[k].t = traj.t[k];
    states[k].T_WB = Pose(Quat(traj.R[k]), traj.p[k]);
    states[k].has_velocity = true;
  }
  const eval::VectorSeries v = eval::readVectorSeries(vel_file);
  requireSameStamps(vel_file, v.t, states);
  for (std::size_t k = 0; k < states.size(); ++k) states[k].v_W = v.value[k];

  const std::string bias_file = (dir / "stamped_bias_estimate.csv").string();
  if (fs::exists(bias_file)) {
    const eval::NumericTable table = eval::readNumericTable(bias_file);
    std::vector<Timestamp> t;
    for (const eval::NumericRow& row : table.rows) {
      if (row.fields.size() != 7)
        throw InputError(bias_file, row.line, "expected 7 columns (timestamp [ns], b_w xyz, b_a xyz), found " +
                                                  std::to_string(row.fields.size()));
      t.push_back(eval::parseNanos(bias_file, row.line, row.fields[0]));
    }
    requireSameStamps(bias_file, t, states);
    for (std::size_t k = 0; k < states.size(); ++k) {
      const eval::NumericRow& row = table.rows[k];
      double b[7];
      for (int i = 1; i < 7; ++i) b[i] = eval::parseFinite(bias_file, row.line, row.fields[i]);
      states[k].gyro_bias = Vec3(b[1], b[2], b[3]);
      states[k].accel_bias = Vec3(b[4], b[5], b[6]);
      states[k].has_biases = true;
    }
  }
  return states;
}

void superviseWithEstimate(const std::string& result_dir, Sequence* seq) {
  std::vector<GroundTruthState> states = readEstimatedStates(result_dir);
  const std::string traj_file = (fs::path(result_dir) / "stamped_traj_estimate.txt").string();
  if (seq->imu.empty()) throw InputError(seq->source, 0, "no IMU samples");
  const Timestamp first = seq->imu.front().t, last = seq->imu.back().t;
  const std::string flight = "the flight's IMU spans " + seconds(first) + "-" + seconds(last) +
                             " s; is this the estimate of " + seq->source + "?";
  if (states.size() < 2 || states.front().t > first + fromSeconds(kMaxEstimateStartDelay) ||
      states.back().t < last - fromSeconds(kMaxEstimateEndGap))
    throw InputError(traj_file, 0, "the estimate (" + seconds(states.front().t) + "-" +
                                       seconds(states.back().t) + " s) does not cover the flight: " + flight);
  for (std::size_t k = 1; k < states.size(); ++k)
    if (states[k].t - states[k - 1].t > fromSeconds(kMaxEstimateGap))
      throw InputError(traj_file, 0,
                       "a gap of " + seconds(states[k].t - states[k - 1].t) + " s in the estimate after " +
                           seconds(states[k - 1].t) + " s");
  seq->groundtruth = std::move(states);
}

}  // namespace hdvio::train
