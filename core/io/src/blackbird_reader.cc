// Blackbird (learned inertial model odometry HDF5 layout). The IMU frame is the body frame and
// the ground truth is already the IMU pose in a z-up world (README), so samples are copied
// without any rotation; the IMU z axis points down when hovering, which FORMATS.md allows.
#include <filesystem>

#include "hdf5_streams.h"
#include "hdvio/core/error.h"
#include "hdvio/io/csv.h"
#include "hdvio/io/datasets.h"
#include "stream_checks.h"

namespace hdvio::io {
namespace fs = std::filesystem;
namespace {

// stamped_groundtruth_imu.txt: "ts x y z qx qy qz qw [vx vy vz]", space separated, seconds.
std::vector<GroundTruthState> readGroundTruthText(const std::string& path, Sequence* seq) {
  CsvReader txt(path, ' ');
  txt.readHeader(true);
  TimeOrder order(path, "groundtruth");
  std::vector<GroundTruthState> out;
  std::string previous_row;
  while (txt.next()) {
    if (txt.size() != 8) txt.expectColumns(11);
    GroundTruthState s;
    s.t = txt.secondsAsNs(0);
    if (!order.accept(s.t, txt.rowText() == previous_row, txt.line())) continue;
    previous_row.assign(txt.rowText());
    const Quat q = unitQuaternion(txt.number(7), txt.number(4), txt.number(5), txt.number(6), path, txt.line());
    s.T_WB = poseExact(q, Vec3(txt.number(1), txt.number(2), txt.number(3)));
    if (txt.size() == 11) {
      s.v_W = Vec3(txt.number(8), txt.number(9), txt.number(10));
      s.has_velocity = true;
    }
    out.push_back(s);
  }
  if (order.duplicates() > 0) seq->warnings.push_back(order.warning());
  return out;
}

}  // namespace

Sequence readBlackbird(const std::string& path, const ReadOptions& options) {
  fs::path h5 = path;
  if (fs::is_directory(h5)) h5 /= "data.hdf5";
  const fs::path folder = fs::weakly_canonical(fs::absolute(h5)).parent_path();
  const Hdf5File file(h5.string());

  Sequence seq;
  seq.source = fs::weakly_canonical(fs::absolute(h5)).string();
  seq.name = folder.parent_path().filename().string() + "_" + folder.filename().string();

  const Hdf5Matrix ts = file.readChecked("ts", -1, 1);
  const long n = static_cast<long>(ts.rows);
  // Calibrated channels (raw minus the stored constant biases) are what the learned inertial
  // odometry release trains on; in the shipped files the biases are zero and both agree.
  const Hdf5Matrix gyro = file.readChecked("gyro_calib", n, 3);
  const Hdf5Matrix accel = file.readChecked("accel_calib", n, 3);
  const Hdf5Matrix thrust = file.readChecked("thrust", n, 3);

  std::vector<Timestamp> stamps = stampsFromSeconds(file, ts);
  const fs::path gt_path = folder / "stamped_groundtruth_imu.txt";
  if (fs::exists(gt_path)) {
    seq.groundtruth = readGroundTruthText(gt_path.string(), &seq);
    // The text file carries the same clock with nanosecond digits; the HDF5 doubles only keep
    // ~0.2 us at 1.5e9 s. Use the exact stamps when the rows correspond one to one.
    bool same_rows = seq.groundtruth.size() == ts.rows;
    for (std::size_t r = 0; same_rows && r < ts.rows; ++r) {
      Timestamp d = 0;  // stamps far apart overflow the difference: then they differ anyway
      same_rows = !__builtin_sub_overflow(seq.groundtruth[r].t, stamps[r], &d) && d > -1000 && d < 1000;
    }
    if (same_rows) {
      for (std::size_t r = 0; r < ts.rows; ++r) stamps[r] = seq.groundtruth[r].t;
    }
  }

  std::vector<Timestamp> kept_stamps;
  const std::vector<std::size_t> rows = orderedRows(file, stamps, {&gyro, &accel, &thrust}, &kept_stamps, &seq);
  fillImu(file, rows, kept_stamps, gyro, accel, options, &seq);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::size_t r = rows[k];
    seq.thrust.push_back(ThrustSample{kept_stamps[k], Vec3(thrust(r, 0), thrust(r, 1), thrust(r, 2))});
  }
  return seq;
}

}  // namespace hdvio::io
