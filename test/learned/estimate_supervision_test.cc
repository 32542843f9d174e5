// hdvio_train's supervision from an estimate: an hdvio_run result folder's states replace the
// flight's ground truth, and every way the folder can be wrong is one InputError naming a file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "hdvio/core/error.h"
#include "hdvio/learned/flight_samples.h"
#include "hdvio/train/estimate_supervision.h"

namespace hdvio::train {
namespace {
namespace fs = std::filesystem;

// 10 s at 1 m/s along x with a slow climb; IMU 200 Hz, thrust 100 Hz, ground truth 20 Hz.
Sequence flight() {
  Sequence seq;
  seq.source = "synthetic";
  for (int k = 0; k <= 2000; ++k) {
    const Timestamp t = 1'000'000'000LL + k * 5'000'000LL;
    seq.imu.push_back({t, Vec3(0.0, 0.0, 0.1), Vec3(0.0, 0.0, 9.81)});
    if (k % 2 == 0) seq.thrust.push_back({t, Vec3(0.0, 0.0, 9.81)});
    if (k % 10 == 0) {
      GroundTruthState s;
      s.t = t;
      const double ts = 0.005 * k;
      s.T_WB = Pose(Quat(Eigen::AngleAxisd(0.1 * ts, Vec3::UnitZ())), Vec3(ts, 0.0, 1.0 + 0.05 * ts));
      s.v_W = Vec3(1.0, 0.0, 0.05);
      s.gyro_bias = Vec3(0.01, -0.02, 0.0);
      s.accel_bias = Vec3(0.0, 0.1, -0.05);
      s.has_velocity = s.has_biases = true;
      seq.groundtruth.push_back(s);
    }
  }
  return seq;
}

// The states written as hdvio_run writes them (result_writer.cc's three files).
fs::path writeResult(const std::vector<GroundTruthState>& states, const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("hdvio_estimate_" + std::to_string(getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream traj(dir / "stamped_traj_estimate.txt"), vel(dir / "stamped_velocity_estimate.csv"),
      bias(dir / "stamped_bias_estimate.csv");
  traj << "# timestamp[s] tx ty tz qx qy qz qw\n";
  vel << "#timestamp [ns],v_x [m s^-1],v_y [m s^-1],v_z [m s^-1]\n";
  bias << "#timestamp [ns],b_w_x [rad s^-1],b_w_y,b_w_z,b_a_x [m s^-2],b_a_y,b_a_z\n";
  char buf[512];
  for (const GroundTruthState& s : states) {
    const Quat q = s.T_WB.q;
    std::snprintf(buf, sizeof(buf), "%lld.%09lld %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n",
                  static_cast<long long>(s.t / 1'000'000'000LL), static_cast<long long>(s.t % 1'000'000'000LL),
                  s.T_WB.p.x(), s.T_WB.p.y(), s.T_WB.p.z(), q.x(), q.y(), q.z(), q.w());
    traj << buf;
    std::snprintf(buf, sizeof(buf), "%lld,%.9f,%.9f,%.9f\n", static_cast<long long>(s.t), s.v_W.x(),
                  s.v_W.y(), s.v_W.z());
    vel << buf;
    std::snprintf(buf, sizeof(buf), "%lld,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f\n", static_cast<long long>(s.t),
                  s.gyro_bias.x(), s.gyro_bias.y(), s.gyro_bias.z(), s.accel_bias.x(), s.accel_bias.y(),
                  s.accel_bias.z());
    bias << buf;
  }
  return dir;
}

std::string errorOf(const std::string& dir, Sequence seq) {
  try {
    superviseWithEstimate(dir, &seq);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(EstimateSupervision, AnEstimateEqualToTheTruthGivesTheSameTrainingSamples) {
  const Sequence truth = flight();
  const fs::path dir = writeResult(truth.groundtruth, "exact");
  Sequence supervised = flight();
  supervised.groundtruth.clear();
  superviseWithEstimate(dir.string(), &supervised);
  const learned::FlightSamples a = learned::resampleFlight(truth), b = learned::resampleFlight(supervised);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(a.size(), 900u);
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    worst = std::max({worst, (a.p_W[k] - b.p_W[k]).norm(), (a.v_W[k] - b.v_W[k]).norm(),
                      (a.gyro[k] - b.gyro[k]).norm(), (a.force[k] - b.force[k]).norm(),
                      a.q_WB[k].angularDistance(b.q_WB[k])});
  }
  EXPECT_LT(worst, 1e-6);  // the files' 9 decimals
  fs::remove_all(dir);
}

TEST(EstimateSupervision, BadResultFoldersAreOneErrorNamingTheFile) {
  const Sequence seq = flight();
  const fs::path dir = writeResult(seq.groundtruth, "bad");
  const std::string traj = (dir / "stamped_traj_estimate.txt").string();
  const std::string vel = (dir / "stamped_velocity_estimate.csv").string();
  EXPECT_EQ(errorOf(dir.string(), seq), "");

  // An estimate of another stretch of time: it does not cover the flight.
  std::vector<GroundTruthState> late(seq.groundtruth.begin() + 120, seq.groundtruth.end());
  const fs::path late_dir = writeResult(late, "late");
  EXPECT_NE(errorOf(late_dir.string(), seq).find("stamped_traj_estimate.txt: the estimate (7.000-11.000 s) "
                                                 "does not cover the flight"),
            std::string::npos)
      << errorOf(late_dir.string(), seq);
  std::vector<GroundTruthState> short_end(seq.groundtruth.begin(), seq.groundtruth.end() - 40);
  const fs::path short_dir = writeResult(short_end, "short");
  EXPECT_NE(errorOf(short_dir.string(), seq).find("does not cover the flight"), std::string::npos);
  // A gap of a second in the middle.
  std::vector<GroundTruthState> gap = seq.groundtruth;
  gap.erase(gap.begin() + 100, gap.begin() + 120);
  const fs::path gap_dir = writeResult(gap, "gap");
  EXPECT_NE(errorOf(gap_dir.string(), seq).find("a gap of 1.050 s in the estimate after 5.950 s"),
            std::string::npos)
      << errorOf(gap_dir.string(), seq);

  // Velocities that do not belong to the poses; then none at all.
  {
    std::ofstream(vel) << "#timestamp [ns],v_x,v_y,v_z\n1000000000,1,0,0\n";
  }
  EXPECT_NE(errorOf(dir.string(), seq).find(vel + ": 1 rows for the 201 poses"), std::string::npos)
      << errorOf(dir.string(), seq);
  {
    std::ofstream(vel) << "#timestamp [ns],v_x,v_y,v_z\n1000000000,1,0,nan\n";
  }
  EXPECT_NE(errorOf(dir.string(), seq).find(vel + ":2:"), std::string::npos) << errorOf(dir.string(), seq);
  fs::remove(vel);
  EXPECT_NE(errorOf(dir.string(), seq).find(vel + ": missing"), std::string::npos);
  fs::remove(traj);
  EXPECT_NE(errorOf(dir.string(), seq).find(traj + ": missing"), std::string::npos);
  EXPECT_NE(errorOf("/nonexistent/result", seq).find("no such result folder"), std::string::npos);
  for (const fs::path& d : {dir, late_dir, short_dir, gap_dir}) fs::remove_all(d);
}

}  // namespace
}  // namespace hdvio::train
