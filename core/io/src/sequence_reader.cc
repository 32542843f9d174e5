#include "hdvio/io/sequence_reader.h"

#include <filesystem>
#include <fstream>

#include "hdf5_file.h"
#include "hdvio/core/error.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/datasets.h"
#include "hdvio/io/ros_bag.h"

namespace hdvio::io {
namespace fs = std::filesystem;
namespace {

DatasetFormat detectHdf5(const fs::path& h5) {
  const Hdf5File file(h5.string());
  if (file.has("thrust") && file.has("gyro_calib") && file.has("accel_calib")) return DatasetFormat::kBlackbird;
  if (file.has("meas_rpm") && file.has("gyr") && file.has("acc")) return DatasetFormat::kDido;
  std::string names;
  for (const auto& n : file.datasets()) names += (names.empty() ? "" : ", ") + n;
  throw InputError(h5.string(), 0, "HDF5 file is neither Blackbird (ts, gyro_calib, accel_calib, thrust) "
                                   "nor DIDO (ts, acc, gyr, meas_rpm); it holds: " + names);
}

}  // namespace

const char* formatName(DatasetFormat format) {
  switch (format) {
    case DatasetFormat::kAsl: return "asl";
    case DatasetFormat::kBlackbird: return "blackbird";
    case DatasetFormat::kDido: return "dido";
    case DatasetFormat::kNeuroBem: return "neurobem";
    case DatasetFormat::kRosBag: return "rosbag";
  }
  return "?";
}

DatasetFormat detectFormat(const std::string& path) {
  const fs::path p = path;
  if (!fs::exists(p)) throw InputError(path, 0, "no such file or directory");
  if (fs::is_directory(p)) {
    if (fs::is_directory(p / "mav0") || fs::is_directory(p / "imu0")) return DatasetFormat::kAsl;
    if (fs::exists(p / "data.hdf5")) return detectHdf5(p / "data.hdf5");
    throw InputError(path, 0, "unrecognized dataset folder (expected mav0/, imu0/ or data.hdf5)");
  }
  if (isRosBag(path)) return DatasetFormat::kRosBag;
  const std::string ext = p.extension().string();
  if (ext == ".bag") throw InputError(path, 0, "not a ROS bag (no '#ROSBAG V' magic at the start)");
  if (ext == ".hdf5" || ext == ".h5") return detectHdf5(p);
  if (ext == ".csv") {
    std::ifstream in(path);
    std::string header;
    if (!in || !std::getline(in, header)) throw InputError(path, 0, "cannot read file");
    if (("," + header + ",").find(",mot_1,") != std::string::npos) return DatasetFormat::kNeuroBem;
    throw InputError(path, 1, "unrecognized CSV (a NeuroBEM segment names columns t, ..., mot_1..4)");
  }
  throw InputError(path, 0, "unrecognized input (expected an ASL folder, a data.hdf5, a NeuroBEM .csv or a ROS bag)");
}

Sequence readSequence(const std::string& path, const ReadOptions& options) {
  const DatasetFormat format = detectFormat(path);
  if (format != DatasetFormat::kRosBag && !options.bag_topics.empty())
    throw InputError(options.bag_topics, 0, "a topic map applies to ROS bags only, not to " + path);
  if (format != DatasetFormat::kRosBag && !options.calibration.empty())
    throw InputError(options.calibration, 0, "a calibration folder applies to ROS bags only, not to " + path);
  switch (format) {
    case DatasetFormat::kAsl: return readAsl(path, options);
    case DatasetFormat::kBlackbird: return readBlackbird(path, options);
    case DatasetFormat::kDido: return readDido(path, options);
    case DatasetFormat::kNeuroBem: return readNeuroBem(path, options);
    case DatasetFormat::kRosBag: return readRosBag(path, options);
  }
  throw InputError(path, 0, "unsupported format");
}

}  // namespace hdvio::io
