// DIDO HDF5: IMU from acc/gyr (z up when hovering), rotor speeds from meas_rpm, ground truth
// from gt_p, gt_v, gt_q (w, x, y, z). No thrust model is published with the data.
#include <cmath>
#include <filesystem>

#include "hdf5_streams.h"
#include "hdvio/core/error.h"
#include "hdvio/io/datasets.h"
#include "stream_checks.h"

namespace hdvio::io {
namespace fs = std::filesystem;

Sequence readDido(const std::string& path, const ReadOptions& options) {
  fs::path h5 = path;
  if (fs::is_directory(h5)) h5 /= "data.hdf5";
  const Hdf5File file(h5.string());

  Sequence seq;
  seq.source = fs::weakly_canonical(fs::absolute(h5)).string();
  seq.name = fs::weakly_canonical(fs::absolute(h5)).parent_path().filename().string();

  const Hdf5Matrix ts = file.readChecked("ts", -1, 1);
  const long n = static_cast<long>(ts.rows);
  const Hdf5Matrix gyro = file.readChecked("gyr", n, 3);
  const Hdf5Matrix accel = file.readChecked("acc", n, 3);
  Hdf5Matrix rpm = file.read("meas_rpm");
  if (rpm.cols != 4 && rpm.cols != 5)
    throw InputError(file.where("meas_rpm"), 0, "expected 4 or 5 columns, found " + std::to_string(rpm.cols));
  rpm = file.readChecked("meas_rpm", n, rpm.cols);
  const std::size_t first_speed = rpm.cols == 5 ? 1 : 0;  // 5 columns: a timestamp comes first
  const bool has_gt = file.has("gt_p") || file.has("gt_q") || file.has("gt_v");
  Hdf5Matrix gt_p, gt_v, gt_q;
  if (has_gt) {
    gt_p = file.readChecked("gt_p", n, 3);
    gt_v = file.readChecked("gt_v", n, 3);
    gt_q = file.readChecked("gt_q", n, 4);
  }

  std::vector<Timestamp> stamps;
  const std::vector<std::size_t> rows =
      orderedRows(file, stampsFromSeconds(file, ts), {&gyro, &accel, &rpm}, &stamps, &seq);
  fillImu(file, rows, stamps, gyro, accel, options, &seq);

  constexpr double kRpmScale = 1e4 * 2.0 * M_PI / 60.0;  // (rpm / 1e4) -> rad/s
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::size_t r = rows[k];
    RotorSample s;
    s.t = stamps[k];
    for (int i = 0; i < 4; ++i) s.speeds[i] = rpm(r, first_speed + i) * kRpmScale;
    seq.rotor.push_back(s);
    if (has_gt) {
      GroundTruthState g;
      g.t = stamps[k];
      const Quat q = unitQuaternion(gt_q(r, 0), gt_q(r, 1), gt_q(r, 2), gt_q(r, 3), file.where("gt_q"),
                                    static_cast<long>(r) + 1);
      g.T_WB = poseExact(q, Vec3(gt_p(r, 0), gt_p(r, 1), gt_p(r, 2)));
      g.v_W = Vec3(gt_v(r, 0), gt_v(r, 1), gt_v(r, 2));
      g.has_velocity = true;
      seq.groundtruth.push_back(g);
    }
  }

  if (options.thrust_coefficient || options.mass) {
    if (!(options.thrust_coefficient && options.mass))
      throw InputError(seq.source, 0, "DIDO publishes no thrust model: give both thrust coefficient and mass");
    RotorCalibration c;
    c.mass = *options.mass;
    c.thrust_coefficient = *options.thrust_coefficient;
    c.thrust_axis = Vec3::UnitZ();
    seq.rotor_calibration = c;
  }
  return seq;
}

}  // namespace hdvio::io
