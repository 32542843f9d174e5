// NeuroBEM segment CSVs: named columns, time in seconds, body frame = IMU frame (z up when
// hovering), quaternion stored x, y, z, w, position in the z-up world frame, velocity in the
// body frame (rotated to the world here; see docs/datasets.md for the numerical check).
#include <array>
#include <filesystem>
#include <map>

#include "hdvio/core/error.h"
#include "hdvio/io/csv.h"
#include "hdvio/io/datasets.h"
#include "stream_checks.h"

namespace hdvio::io {
namespace fs = std::filesystem;
namespace {

// Column lookup by header name, resolved once; a missing column is an error on the header line.
class Columns {
 public:
  explicit Columns(CsvReader* csv) : csv_(csv) {
    const std::vector<std::string> names = csv->readHeader(/*require_hash=*/false);
    for (std::size_t i = 0; i < names.size(); ++i) index_[names[i]] = i;
    count_ = names.size();
  }
  std::size_t operator[](const std::string& name) const {
    auto it = index_.find(name);
    if (it == index_.end()) throw InputError(csv_->path(), 1, "missing column '" + name + "'");
    return it->second;
  }
  std::array<std::size_t, 3> xyz(const std::string& prefix) const {
    return {(*this)[prefix + "x"], (*this)[prefix + "y"], (*this)[prefix + "z"]};
  }
  Vec3 vec3(const std::array<std::size_t, 3>& c) const {
    return Vec3(csv_->number(c[0]), csv_->number(c[1]), csv_->number(c[2]));
  }
  std::size_t count() const { return count_; }

 private:
  CsvReader* csv_;
  std::map<std::string, std::size_t> index_;
  std::size_t count_ = 0;
};

}  // namespace

Sequence readNeuroBem(const std::string& csv_path, const ReadOptions& options) {
  CsvReader csv(csv_path);
  const Columns col(&csv);
  const std::size_t t_col = col["t"];
  const auto gyro_cols = col.xyz("ang_vel_"), acc_cols = col.xyz("acc_"), vel_cols = col.xyz("vel_"),
             pos_cols = col.xyz("pos_");
  const std::array<std::size_t, 4> quat_cols = {col["quat_w"], col["quat_x"], col["quat_y"], col["quat_z"]};
  const std::array<std::size_t, 4> mot_cols = {col["mot_1"], col["mot_2"], col["mot_3"], col["mot_4"]};

  Sequence seq;
  seq.source = fs::weakly_canonical(fs::absolute(csv_path)).string();
  seq.name = fs::path(csv_path).stem().string();
  TimeOrder order(csv_path, "imu0");
  std::string previous_row;
  while (csv.next()) {
    csv.expectColumns(col.count());
    const Timestamp t = csv.secondsAsNs(t_col);
    if (!order.accept(t, csv.rowText() == previous_row, csv.line())) continue;
    previous_row.assign(csv.rowText());
    if (!seq.imu.empty()) checkImuGap(seq.imu.back().t, t, options.max_imu_gap_s, csv_path, csv.line());

    ImuSample imu;
    imu.t = t;
    imu.gyro = col.vec3(gyro_cols);
    imu.accel = col.vec3(acc_cols);
    seq.imu.push_back(imu);

    RotorSample rotor;
    rotor.t = t;
    for (int i = 0; i < 4; ++i) rotor.speeds[i] = csv.number(mot_cols[i]);
    seq.rotor.push_back(rotor);

    GroundTruthState g;
    g.t = t;
    const Quat q = unitQuaternion(csv.number(quat_cols[0]), csv.number(quat_cols[1]),
                                  csv.number(quat_cols[2]), csv.number(quat_cols[3]), csv_path, csv.line());
    g.T_WB = poseExact(q, col.vec3(pos_cols));
    g.v_W = q * col.vec3(vel_cols);  // vel_* is body-frame: checked against d/dt pos_*
    g.has_velocity = true;
    seq.groundtruth.push_back(g);
  }
  if (seq.imu.empty()) throw InputError(csv_path, 0, "no samples");
  if (order.duplicates() > 0) seq.warnings.push_back(order.warning());

  if (options.thrust_coefficient) {
    RotorCalibration c;
    c.mass = options.mass.value_or(kNeuroBemMass);
    c.thrust_coefficient = *options.thrust_coefficient;
    c.thrust_axis = Vec3::UnitZ();
    if (!(c.mass > 0 && c.thrust_coefficient > 0)) throw InputError(csv_path, 0, "mass and thrust coefficient must be positive");
    seq.rotor_calibration = c;
  } else {
    seq.warnings.push_back("rotor0: no thrust coefficient published for NeuroBEM; pass one (mass " +
                           std::to_string(options.mass.value_or(kNeuroBemMass)) +
                           " kg) to derive thrust from rotor speeds");
  }
  return seq;
}

std::vector<NeuroBemForceSample> readNeuroBemForces(const std::string& csv_path) {
  CsvReader csv(csv_path);
  const Columns col(&csv);
  const std::size_t t_col = col["t"];
  const auto f_cols = col.xyz("neurobem_f_"), tau_cols = col.xyz("neurobem_tau_"),
             rf_cols = col.xyz("residual_f_"), rtau_cols = col.xyz("residual_tau_");
  std::vector<NeuroBemForceSample> out;
  TimeOrder order(csv_path, "neurobem forces");
  std::string previous_row;
  while (csv.next()) {
    csv.expectColumns(col.count());
    NeuroBemForceSample s;
    s.t = csv.secondsAsNs(t_col);
    if (!order.accept(s.t, csv.rowText() == previous_row, csv.line())) continue;
    previous_row.assign(csv.rowText());
    s.force = col.vec3(f_cols);
    s.torque = col.vec3(tau_cols);
    s.residual_force = col.vec3(rf_cols);
    s.residual_torque = col.vec3(rtau_cols);
    out.push_back(s);
  }
  if (out.empty()) throw InputError(csv_path, 0, "no samples");
  return out;
}

}  // namespace hdvio::io
