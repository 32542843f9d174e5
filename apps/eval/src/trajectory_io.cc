#include "hdvio/eval/trajectory_io.h"

#include <cmath>
#include <filesystem>

#include "hdvio/core/error.h"
#include "hdvio/eval/text_table.h"

namespace hdvio::eval {
namespace fs = std::filesystem;
namespace {

// Quaternions written with 6-9 decimals are a little off unit length; more than this is a bug
// in the file, not round-off.
constexpr double kMaxQuaternionNormError = 1e-2;

Mat3 rotationFromQuaternion(const std::string& file, long line, double w, double x, double y,
                            double z) {
  const Quat q(w, x, y, z);
  const double norm = q.norm();
  if (std::fabs(norm - 1.0) > kMaxQuaternionNormError)
    throw InputError(file, line, "quaternion is not unit length (norm " + std::to_string(norm) + ")");
  return q.normalized().toRotationMatrix();
}

void requireColumns(const std::string& file, const NumericRow& row, std::size_t expected,
                    const std::string& what) {
  if (row.fields.size() != expected)
    throw InputError(file, row.line,
                     "expected " + std::to_string(expected) + " columns (" + what + "), found " +
                         std::to_string(row.fields.size()));
}

std::vector<long> lineNumbers(const NumericTable& table) {
  std::vector<long> lines;
  for (const auto& row : table.rows) lines.push_back(row.line);
  return lines;
}

void requireData(const NumericTable& table) {
  if (table.rows.empty()) throw InputError(table.file, 0, "no data lines");
}

std::string aslMav0(const std::string& folder) {
  if (fs::exists(fs::path(folder) / "mav0")) return (fs::path(folder) / "mav0").string();
  return folder;
}

}  // namespace

TrajectoryFormat parseTrajectoryFormat(const std::string& name) {
  if (name == "auto") return TrajectoryFormat::kAuto;
  if (name == "tum") return TrajectoryFormat::kTum;
  if (name == "kitti") return TrajectoryFormat::kKitti;
  if (name == "euroc") return TrajectoryFormat::kEuroc;
  if (name == "asl") return TrajectoryFormat::kAslFolder;
  throw InputError("", 0, "unknown trajectory format '" + name + "' (auto|tum|kitti|euroc|asl)");
}

std::string formatName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kAuto: return "auto";
    case TrajectoryFormat::kTum: return "tum";
    case TrajectoryFormat::kKitti: return "kitti";
    case TrajectoryFormat::kEuroc: return "euroc";
    case TrajectoryFormat::kAslFolder: return "asl";
  }
  return "?";
}

Trajectory readTumTrajectory(const std::string& path) {
  const NumericTable table = readNumericTable(path);
  requireData(table);
  Trajectory traj;
  traj.source = path;
  traj.reserve(table.rows.size());
  const std::size_t columns = table.rows.front().fields.size();
  if (columns != 8 && columns != 11)
    throw InputError(path, table.rows.front().line,
                     "expected 8 columns (t tx ty tz qx qy qz qw) or 11 (... vx vy vz), found " +
                         std::to_string(columns));
  for (const auto& row : table.rows) {
    requireColumns(path, row, columns, columns == 8 ? "t tx ty tz qx qy qz qw"
                                                    : "t tx ty tz qx qy qz qw vx vy vz");
    double f[11];
    for (std::size_t i = 1; i < columns; ++i) f[i] = parseFinite(path, row.line, row.fields[i]);
    const Timestamp t = parseSecondsAsNanos(path, row.line, row.fields[0]);
    traj.push(t, Vec3(f[1], f[2], f[3]), rotationFromQuaternion(path, row.line, f[7], f[4], f[5], f[6]));
    if (columns == 11) traj.v.emplace_back(f[8], f[9], f[10]);
  }
  traj.repeated_stamps = requireNonDecreasing(path, traj.t, lineNumbers(table));
  return traj;
}

Trajectory readKittiPoses(const std::string& path) {
  const NumericTable table = readNumericTable(path);
  requireData(table);
  Trajectory traj;
  traj.source = path;
  traj.has_timestamps = false;
  traj.reserve(table.rows.size());
  Timestamp index = 0;
  for (const auto& row : table.rows) {
    requireColumns(path, row, 12, "row-major 3x4 [R|t]");
    double f[12];
    for (int i = 0; i < 12; ++i) f[i] = parseFinite(path, row.line, row.fields[i]);
    Mat3 R;
    R << f[0], f[1], f[2], f[4], f[5], f[6], f[8], f[9], f[10];
    // Kept as read (evo does the same); only reject matrices that are not rotations at all.
    if ((R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-2 || R.determinant() < 0)
      throw InputError(path, row.line, "the 3x3 block is not a rotation matrix");
    traj.push(index * kNanosPerSecond, Vec3(f[3], f[7], f[11]), R);
    ++index;
  }
  return traj;
}

Trajectory readEurocGroundTruth(const std::string& path) {
  const NumericTable table = readNumericTable(path);
  requireData(table);
  Trajectory traj;
  traj.source = path;
  traj.reserve(table.rows.size());
  const std::size_t columns = table.rows.front().fields.size();
  if (columns < 8)
    throw InputError(path, table.rows.front().line,
                     "expected at least 8 columns (timestamp [ns], p_RS_R xyz, q_RS wxyz), found " +
                         std::to_string(columns));
  const bool with_velocity = columns >= 11;
  for (const auto& row : table.rows) {
    requireColumns(path, row, columns, "EuRoC state ground truth");
    const Timestamp t = parseNanos(path, row.line, row.fields[0]);
    std::vector<double> f(columns);
    for (std::size_t i = 1; i < columns; ++i) f[i] = parseFinite(path, row.line, row.fields[i]);
    traj.push(t, Vec3(f[1], f[2], f[3]), rotationFromQuaternion(path, row.line, f[4], f[5], f[6], f[7]));
    if (with_velocity) traj.v.emplace_back(f[8], f[9], f[10]);
  }
  traj.repeated_stamps = requireNonDecreasing(path, traj.t, lineNumbers(table));
  return traj;
}

Trajectory readAslGroundTruth(const std::string& folder) {
  const fs::path file = fs::path(aslMav0(folder)) / "state_groundtruth_estimate0" / "data.csv";
  if (!fs::exists(file))
    throw InputError(folder, 0, "ASL folder has no state_groundtruth_estimate0/data.csv");
  return readEurocGroundTruth(file.string());
}

std::optional<std::string> aslForceGroundTruthPath(const std::string& folder) {
  const fs::path file = fs::path(aslMav0(folder)) / "force_groundtruth0" / "data.csv";
  if (fs::exists(file)) return file.string();
  return std::nullopt;
}

TrajectoryFormat detectTrajectoryFormat(const std::string& path) {
  if (fs::is_directory(path)) return TrajectoryFormat::kAslFolder;
  const NumericTable table = readNumericTable(path);
  requireData(table);
  const NumericRow& first = table.rows.front();
  const std::size_t columns = first.fields.size();
  if (columns == 12) return TrajectoryFormat::kKitti;
  const bool integer_stamp = first.fields[0].find_first_not_of("0123456789") == std::string::npos;
  // EuRoC stamps are integer ns (>= 1e12 for any real clock); TUM stamps are seconds.
  if (columns >= 8 && integer_stamp && first.fields[0].size() >= 13) return TrajectoryFormat::kEuroc;
  if (columns == 8 || columns == 11) return TrajectoryFormat::kTum;
  throw InputError(path, first.line,
                   "cannot tell the trajectory format from " + std::to_string(columns) +
                       " columns (TUM: 8 or 11, KITTI: 12, EuRoC CSV: integer ns stamp + >= 7)");
}

Trajectory readTrajectory(const std::string& path, TrajectoryFormat format) {
  if (!fs::exists(path)) throw InputError(path, 0, "no such file or folder");
  if (format == TrajectoryFormat::kAuto) format = detectTrajectoryFormat(path);
  switch (format) {
    case TrajectoryFormat::kTum: return readTumTrajectory(path);
    case TrajectoryFormat::kKitti: return readKittiPoses(path);
    case TrajectoryFormat::kEuroc: return readEurocGroundTruth(path);
    case TrajectoryFormat::kAslFolder: return readAslGroundTruth(path);
    case TrajectoryFormat::kAuto: break;
  }
  throw InputError(path, 0, "unknown trajectory format");
}

namespace {
Timestamp parseStamp(const std::string& file, long line, const std::string& field) {
  return field.find_first_of(".eE") == std::string::npos ? parseNanos(file, line, field)
                                                         : parseSecondsAsNanos(file, line, field);
}
}  // namespace

VectorSeries readVectorSeries(const std::string& path) {
  const NumericTable table = readNumericTable(path);
  requireData(table);
  VectorSeries series;
  series.source = path;
  for (const auto& row : table.rows) {
    requireColumns(path, row, 4, "timestamp, x, y, z");
    series.t.push_back(parseStamp(path, row.line, row.fields[0]));
    series.value.emplace_back(parseFinite(path, row.line, row.fields[1]),
                              parseFinite(path, row.line, row.fields[2]),
                              parseFinite(path, row.line, row.fields[3]));
  }
  requireIncreasing(path, series.t, lineNumbers(table));
  return series;
}

ForceGroundTruth readForceGroundTruth(const std::string& path) {
  const NumericTable table = readNumericTable(path);
  requireData(table);
  ForceGroundTruth forces;
  forces.source = path;
  for (const auto& row : table.rows) {
    requireColumns(path, row, 7, "timestamp [ns], f_ext xyz, f_drag xyz");
    forces.t.push_back(parseStamp(path, row.line, row.fields[0]));
    double f[7];
    for (int i = 1; i < 7; ++i) f[i] = parseFinite(path, row.line, row.fields[i]);
    forces.external.emplace_back(f[1], f[2], f[3]);
    forces.drag.emplace_back(f[4], f[5], f[6]);
  }
  requireIncreasing(path, forces.t, lineNumbers(table));
  return forces;
}

}  // namespace hdvio::eval
