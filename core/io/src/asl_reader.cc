#include <filesystem>

#include "hdvio/core/error.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/csv.h"
#include "sensor_yaml.h"
#include "stream_checks.h"

namespace hdvio::io {
namespace fs = std::filesystem;
namespace {

// Reads a "#timestamp [ns],..." CSV with a fixed column count; calls add(csv, t) for every
// kept row, in strictly increasing time order.
template <class AddRow>
void readTimedCsv(const fs::path& file, const std::string& stream, std::size_t columns,
                  Sequence* seq, AddRow add) {
  CsvReader csv(file.string());
  csv.readHeader(/*require_hash=*/true);
  TimeOrder order(file.string(), stream);
  std::string previous_row;
  while (csv.next()) {
    csv.expectColumns(columns);
    const Timestamp t = csv.timestampNs(0);
    if (!order.accept(t, csv.rowText() == previous_row, csv.line())) continue;
    add(csv, t);
    previous_row.assign(csv.rowText());
  }
  if (order.duplicates() > 0) seq->warnings.push_back(order.warning());
}

Vec3 vec3At(const CsvReader& csv, std::size_t first) {
  return Vec3(csv.number(first), csv.number(first + 1), csv.number(first + 2));
}

void readImu(const fs::path& dir, const ReadOptions& options, Sequence* seq) {
  const fs::path file = dir / "data.csv";
  readTimedCsv(file, "imu0", 7, seq, [&](const CsvReader& csv, Timestamp t) {
    if (!seq->imu.empty())
      checkImuGap(seq->imu.back().t, t, options.max_imu_gap_s, file.string(), csv.line());
    ImuSample s;
    s.t = t;
    s.gyro = vec3At(csv, 1);
    s.accel = vec3At(csv, 4);
    seq->imu.push_back(s);
  });
  if (seq->imu.empty()) throw InputError(file.string(), 0, "no IMU samples");
  if (fs::exists(dir / "sensor.yaml")) seq->imu_calibration = readImuSensorYaml((dir / "sensor.yaml").string());
}

void readCamera(const fs::path& dir, const ReadOptions& options, Sequence* seq) {
  const fs::path yaml = dir / "sensor.yaml";
  if (!fs::exists(yaml)) throw InputError(yaml.string(), 0, "missing camera calibration file");
  seq->camera = readCameraSensorYaml(yaml.string());
  const fs::path file = dir / "data.csv";
  const fs::path image_dir = fs::absolute(dir / "data");
  readTimedCsv(file, "cam0", 2, seq, [&](const CsvReader& csv, Timestamp t) {
    const fs::path image = image_dir / std::string(csv.text(1));
    if (options.check_images_exist && !fs::is_regular_file(image))
      csv.fail("image file does not exist: " + image.string());
    seq->images.push_back(
        ImageRef{t, image.lexically_normal().string(), std::nullopt, file.string(), csv.line()});
  });
}

void readGroundTruth(const fs::path& file, Sequence* seq) {
  CsvReader csv(file.string());
  csv.readHeader(true);
  TimeOrder order(file.string(), "state_groundtruth_estimate0");
  std::string previous_row;
  std::size_t columns = 0;
  while (csv.next()) {
    if (columns == 0) {
      columns = csv.size();
      if (columns != 8 && columns != 11 && columns != 17)
        csv.fail("expected 17 columns (t, p, q, v, b_w, b_a), or 8 / 11; found " + std::to_string(columns));
    }
    csv.expectColumns(columns);
    const Timestamp t = csv.timestampNs(0);
    if (!order.accept(t, csv.rowText() == previous_row, csv.line())) continue;
    previous_row.assign(csv.rowText());
    GroundTruthState s;
    s.t = t;
    const Quat q = unitQuaternion(csv.number(4), csv.number(5), csv.number(6), csv.number(7),
                                  file.string(), csv.line());
    s.T_WB = poseExact(q, vec3At(csv, 1));
    if (columns >= 11) {
      s.v_W = vec3At(csv, 8);
      s.has_velocity = true;
    }
    if (columns == 17) {
      s.gyro_bias = vec3At(csv, 11);
      s.accel_bias = vec3At(csv, 14);
      s.has_biases = true;
    }
    seq->groundtruth.push_back(s);
  }
  if (order.duplicates() > 0) seq->warnings.push_back(order.warning());
}

void readLandmarks(const fs::path& dir, Sequence* seq) {
  const fs::path points = dir / "points.csv";
  CsvReader pcsv(points.string());
  pcsv.readHeader(true);
  while (pcsv.next()) {
    pcsv.expectColumns(4);
    const long long id = pcsv.integer(0);
    if (id < 0 || id > 2147483647LL) pcsv.fail("landmark id out of range");
    if (!seq->landmarks.emplace(static_cast<int>(id), vec3At(pcsv, 1)).second)
      pcsv.fail("duplicate landmark id " + std::to_string(id));
  }
  const fs::path obs = dir / "data.csv";
  CsvReader csv(obs.string());
  csv.readHeader(true);
  std::string previous_row;
  int duplicates = 0;
  while (csv.next()) {
    csv.expectColumns(4);
    if (csv.rowText() == previous_row) {
      ++duplicates;
      continue;
    }
    previous_row.assign(csv.rowText());
    LandmarkObservation o;
    o.t = csv.timestampNs(0);
    o.landmark_id = static_cast<int>(csv.integer(1));
    o.u = csv.number(2);
    o.v = csv.number(3);
    if (!seq->landmark_observations.empty() && o.t < seq->landmark_observations.back().t)
      csv.fail("non-monotonic timestamp " + std::to_string(o.t));
    if (!seq->landmarks.count(o.landmark_id))
      csv.fail("landmark id " + std::to_string(o.landmark_id) + " is not in points.csv");
    seq->landmark_observations.push_back(o);
  }
  if (duplicates > 0) {
    seq->warnings.push_back("landmarks0: dropped " + std::to_string(duplicates) +
                            " exactly duplicated rows (" + obs.string() + ")");
  }
}

}  // namespace

Sequence readAsl(const std::string& folder, const ReadOptions& options) {
  fs::path root = folder;
  if (!fs::is_directory(root)) throw InputError(folder, 0, "not a directory");
  if (fs::is_directory(root / "mav0")) root /= "mav0";
  const fs::path canonical = fs::weakly_canonical(fs::absolute(root));
  if (!fs::is_directory(root / "imu0"))
    throw InputError(folder, 0, "not an ASL sequence: no mav0/imu0 folder (imu0 is required)");

  Sequence seq;
  seq.source = canonical.string();
  seq.name = canonical.filename() == "mav0" ? canonical.parent_path().filename().string()
                                             : canonical.filename().string();

  readImu(root / "imu0", options, &seq);
  if (fs::is_directory(root / "cam0")) readCamera(root / "cam0", options, &seq);
  if (fs::is_directory(root / "thrust0")) {
    readTimedCsv(root / "thrust0" / "data.csv", "thrust0", 4, &seq, [&](const CsvReader& csv, Timestamp t) {
      seq.thrust.push_back(ThrustSample{t, vec3At(csv, 1)});
    });
  }
  if (fs::is_directory(root / "rotor0")) {
    readTimedCsv(root / "rotor0" / "data.csv", "rotor0", 5, &seq, [&](const CsvReader& csv, Timestamp t) {
      RotorSample s;
      s.t = t;
      s.speeds = Eigen::Vector4d(csv.number(1), csv.number(2), csv.number(3), csv.number(4));
      seq.rotor.push_back(s);
    });
    const fs::path yaml = root / "rotor0" / "sensor.yaml";
    if (fs::exists(yaml)) seq.rotor_calibration = readRotorSensorYaml(yaml.string());
  }
  applyRotorOptions(options, (root / "rotor0").string(), &seq);
  const fs::path gt = root / "state_groundtruth_estimate0" / "data.csv";
  if (fs::is_directory(gt.parent_path())) readGroundTruth(gt, &seq);
  if (fs::is_directory(root / "force_groundtruth0")) {
    readTimedCsv(root / "force_groundtruth0" / "data.csv", "force_groundtruth0", 7, &seq,
                 [&](const CsvReader& csv, Timestamp t) {
                   seq.forces.push_back(ForceSample{t, vec3At(csv, 1), vec3At(csv, 4)});
                 });
  }
  if (fs::is_directory(root / "landmarks0")) readLandmarks(root / "landmarks0", &seq);
  return seq;
}

}  // namespace hdvio::io
