// Real data: IMU preintegration over the EuRoC V1_01 excerpt agrees with the ground-truth
// states (checks frames, gravity sign and bias conventions on a real sensor).
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "hdvio/factors/imu_factor.h"

namespace hdvio {
namespace {

const std::string kMav = std::string(HDVIO_DATA_DIR) + "/euroc/V1_01_easy_excerpt/mav0";

std::vector<std::vector<double>> readCsv(const std::string& path, std::vector<Timestamp>* stamps) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string cell;
    std::getline(ss, cell, ',');
    stamps->push_back(std::stoll(cell));
    std::vector<double> row;
    while (std::getline(ss, cell, ',')) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

TEST(EurocImu, PreintegrationMatchesGroundTruth) {
  std::ifstream probe(kMav + "/imu0/data.csv");
  if (!probe) GTEST_SKIP() << "EuRoC excerpt not found under " << kMav;
  std::vector<Timestamp> t_imu, t_gt;
  const auto imu_rows = readCsv(kMav + "/imu0/data.csv", &t_imu);
  const auto gt = readCsv(kMav + "/state_groundtruth_estimate0/data.csv", &t_gt);
  ASSERT_GT(imu_rows.size(), 500u);
  ASSERT_GT(gt.size(), 50u);
  std::vector<ImuSample> imu;
  for (std::size_t k = 0; k < imu_rows.size(); ++k)
    imu.push_back({t_imu[k], Vec3(imu_rows[k][0], imu_rows[k][1], imu_rows[k][2]),
                   Vec3(imu_rows[k][3], imu_rows[k][4], imu_rows[k][5])});
  auto state = [&](std::size_t k) {
    const auto& r = gt[k];
    struct S { Mat3 R; Vec3 p, v; Vec6 b; } s;
    s.p = Vec3(r[0], r[1], r[2]);
    s.R = Quat(r[3], r[4], r[5], r[6]).normalized().toRotationMatrix();
    s.v = Vec3(r[7], r[8], r[9]);
    s.b << r[10], r[11], r[12], r[13], r[14], r[15];
    return s;
  };
  const ImuNoiseParams params;
  double worst_rot = 0, worst_vel = 0, worst_pos = 0;
  int intervals = 0;
  for (std::size_t i = 1; i + 5 < gt.size(); i += 5) {  // 0.25 s intervals
    const std::size_t j = i + 5;
    if (t_gt[i] < imu.front().t || t_gt[j] > imu.back().t) continue;
    const auto si = state(i), sj = state(j);
    const auto pim = PreintegratedImu::integrate(imu, t_gt[i], t_gt[j], si.b, params);
    const double dt = pim.dt();
    const Vec3 g = params.gravity;
    const Mat3 RiT = si.R.transpose();
    worst_rot = std::max(worst_rot, so3Log(pim.deltaR().transpose() * RiT * sj.R).norm());
    worst_vel = std::max(worst_vel, (RiT * (sj.v - si.v - g * dt) - pim.deltaV()).norm());
    worst_pos = std::max(worst_pos, (RiT * (sj.p - si.p - si.v * dt - 0.5 * g * dt * dt) - pim.deltaP()).norm());
    ++intervals;
  }
  std::printf("EuRoC V1_01 excerpt, %d intervals of 0.25 s: worst rotation %.4f rad, velocity %.4f m/s, "
              "position %.4f m\n", intervals, worst_rot, worst_vel, worst_pos);
  ASSERT_GE(intervals, 15);
  // Ground truth is a Vicon-based estimate; a wrong gravity sign or frame would give metres per
  // second here (2 g dt = 4.9 m/s).
  EXPECT_LT(worst_rot, 0.01);
  EXPECT_LT(worst_vel, 0.05);
  EXPECT_LT(worst_pos, 0.01);
}

}  // namespace
}  // namespace hdvio
