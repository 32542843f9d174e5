// ROS 1 bag -> Sequence: the topic map picks the topics, ros_messages decodes them, the
// calibration (an ASL folder or Kalibr files) adds what a bag does not carry.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <vector>

#include "bag_format.h"
#include "hdvio/core/config.h"
#include "hdvio/core/error.h"
#include "hdvio/io/ros_bag.h"
#include "kalibr_yaml.h"
#include "ros_messages.h"
#include "sensor_yaml.h"
#include "stream_checks.h"

namespace hdvio::io {
namespace fs = std::filesystem;
namespace {

enum class Role { kImu, kCamera, kRotor, kThrust, kGroundTruth };

struct Stream {
  Role role;
  const char* key;  // topic-map key and stream name in errors
  std::string topic;
  std::vector<std::string> types;
};

// One decoded message waiting to be put in time order.
template <class Sample>
struct Pending {
  Timestamp record_time = 0;
  Sample sample;
  std::string bytes;  // kept to tell an exact duplicate message from a conflicting one
};

// An image message: its stamp, size and place in the bag.
struct BagImage {
  Timestamp t = 0;
  ros::ImageHeader header;
  ContainerSpan span;
};

std::string joined(const std::vector<std::string>& items) {
  std::string s;
  for (const auto& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

// Orders one stream by record time (as rosbag plays it), then requires strictly increasing
// header stamps, dropping exact duplicates with a warning.
template <class Sample, class Add>
void emit(std::vector<Pending<Sample>>* pending, const std::string& file, const std::string& topic,
          Sequence* seq, Add add) {
  std::stable_sort(pending->begin(), pending->end(),
                   [](const auto& a, const auto& b) { return a.record_time < b.record_time; });
  TimeOrder order(file, topic);
  const std::string* previous = nullptr;
  for (std::size_t i = 0; i < pending->size(); ++i) {
    const Pending<Sample>& p = (*pending)[i];
    bool keep = true;
    try {
      keep = order.accept(p.sample.t, previous && !p.bytes.empty() && *previous == p.bytes, 0);
    } catch (const InputError& e) {
      throw InputError(file, 0, topic + " message " + std::to_string(i + 1) + " (in record-time order): " + e.problem());
    }
    if (keep) add(p.sample, i);
    previous = &p.bytes;
  }
  if (order.duplicates() > 0) seq->warnings.push_back(order.warning());
}

// What the calibration adds beyond the sensor files: Kalibr's camera time shift, and whether the
// camera rate has to come from the image stamps (camchains carry none).
struct CalibrationExtras {
  double timeshift_cam_imu = 0.0;
  bool camera_rate_from_stamps = false;
  std::optional<Pose> groundtruth_T_BS;  // ground-truth sensor (mocap marker) -> body
};

CalibrationExtras readAslCalibration(const std::string& folder, bool has_images, Sequence* seq) {
  fs::path root = folder;
  if (fs::is_directory(root / "mav0")) root /= "mav0";
  const fs::path cam = root / "cam0" / "sensor.yaml", imu = root / "imu0" / "sensor.yaml";
  if (!fs::exists(imu)) throw InputError(imu.string(), 0, "missing IMU calibration file");
  seq->imu_calibration = readImuSensorYaml(imu.string());
  if (has_images) {
    if (!fs::exists(cam)) throw InputError(cam.string(), 0, "missing camera calibration file (the bag holds images)");
    seq->camera = readCameraSensorYaml(cam.string());
  }
  const fs::path rotor = root / "rotor0" / "sensor.yaml";
  if (fs::exists(rotor)) seq->rotor_calibration = readRotorSensorYaml(rotor.string());
  CalibrationExtras extras;
  const fs::path vicon = root / "vicon0" / "sensor.yaml";
  if (fs::exists(vicon)) extras.groundtruth_T_BS = readSensorExtrinsics(vicon.string());
  return extras;
}

CalibrationExtras readKalibrCalibration(const std::string& files, bool has_images, Sequence* seq) {
  KalibrCalibration k;
  std::size_t begin = 0;
  while (begin <= files.size()) {
    const std::size_t comma = std::min(files.find(',', begin), files.size());
    const std::string file = files.substr(begin, comma - begin);
    if (!fs::is_regular_file(file))
      throw InputError(file.empty() ? "--calibration" : file, 0,
                       "calibration folder or file does not exist (--calibration takes an ASL folder or Kalibr files: "
                       "camchain.yaml,imu.yaml[,rotor0 / vicon0 sensor.yaml])");
    readKalibrYaml(file, &k);
    begin = comma + 1;
  }
  if (!k.imu) throw InputError(files, 0, "no Kalibr IMU file (imu.yaml with the noise densities) among the calibration files");
  if (has_images && !k.camera)
    throw InputError(files, 0, "the bag holds images but no Kalibr camchain (camchain-imucam.yaml) was given");
  seq->imu_calibration = k.imu;
  seq->rotor_calibration = k.rotor;
  CalibrationExtras extras;
  extras.groundtruth_T_BS = k.groundtruth_T_BS;
  if (has_images) {
    // The camchain gives camera -> IMU; the sequence wants camera -> body.
    CameraCalibration camera = *k.camera;
    camera.T_BS = k.imu->T_BS * camera.T_BS;
    seq->camera = camera;
    extras.timeshift_cam_imu = k.timeshift_cam_imu;
    extras.camera_rate_from_stamps = true;
  }
  for (const std::string& w : k.warnings) seq->warnings.push_back(w);
  return extras;
}

// --calibration: an ASL folder (cam0/imu0/rotor0 sensor.yaml, or its mav0 parent), or Kalibr
// files separated by commas.
CalibrationExtras readCalibration(const std::string& spec, bool has_images, Sequence* seq) {
  if (spec.empty()) {
    if (has_images)
      throw InputError("--calibration", 0, "the bag holds images but bags carry no calibration: pass "
                                           "--calibration <folder with cam0/sensor.yaml and imu0/sensor.yaml> "
                                           "or Kalibr's <camchain-imucam.yaml>,<imu.yaml>");
    return {};
  }
  if (fs::is_directory(spec)) return readAslCalibration(spec, has_images, seq);
  return readKalibrCalibration(spec, has_images, seq);
}

// Kalibr's camera clock correction (t_imu = t_cam + shift), the ground truth moved from the
// mocap marker to the body, and, for a camchain, the camera rate from the stamps.
void applyCalibrationExtras(const CalibrationExtras& extras, const std::string& path, Sequence* seq) {
  if (extras.timeshift_cam_imu != 0.0) {
    const Timestamp shift = fromSeconds(extras.timeshift_cam_imu);
    for (ImageRef& image : seq->images) image.t += shift;
    seq->warnings.push_back("image stamps moved by Kalibr's timeshift_cam_imu (" +
                            std::to_string(extras.timeshift_cam_imu) + " s) to the IMU clock");
  }
  if (extras.groundtruth_T_BS && !seq->groundtruth.empty()) {
    // EuRoC's Vicon topic is the marker's pose: body = marker * (body -> marker).
    const Pose T_SB = extras.groundtruth_T_BS->inverse();
    const bool moved = T_SB.p.norm() > 0.0;
    std::size_t dropped = 0;
    for (GroundTruthState& g : seq->groundtruth) {
      g.T_WB = g.T_WB * T_SB;
      // The marker's velocity is not the body's when they are apart (it needs the rate).
      if (moved && g.has_velocity) {
        g.has_velocity = false;
        g.v_W.setZero();
        ++dropped;
      }
    }
    seq->warnings.push_back("ground truth moved from the marker to the body frame (vicon0/sensor.yaml T_BS)" +
                            (dropped ? "; " + std::to_string(dropped) + " marker velocities dropped" : std::string()));
  }
  if (extras.camera_rate_from_stamps && seq->camera) {
    if (seq->images.size() < 2)
      throw InputError(path, 0, "a Kalibr camchain carries no camera rate and the bag has fewer than 2 images");
    seq->camera->rate_hz = static_cast<double>(seq->images.size() - 1) /
                           secondsBetween(seq->images.front().t, seq->images.back().t);
  }
}

}  // namespace

BagTopicMap readBagTopicMap(const std::string& yaml_path) {
  const ConfigReader cfg = ConfigReader::fromFile(yaml_path);
  BagTopicMap map;
  for (auto [key, topic] : {std::pair<const char*, std::string*>{"imu", &map.imu}, {"camera", &map.camera},
                            {"rotor_speeds", &map.rotor_speeds}, {"thrust", &map.thrust},
                            {"groundtruth", &map.groundtruth}}) {
    if (!cfg.has(key)) continue;
    cfg.read(key, topic);
    map.named.insert(key);
  }
  std::vector<double> axis = {0.0, 0.0, 1.0};
  cfg.readVector("thrust_axis", &axis, 3);
  map.thrust_axis = Vec3(axis[0], axis[1], axis[2]);
  if (std::abs(map.thrust_axis.norm() - 1.0) > 1e-6) throw InputError(yaml_path, 0, "thrust_axis must be a unit vector");
  if (map.imu.empty()) throw InputError(yaml_path, 0, "imu: a topic is required");
  cfg.finish();
  return map;
}

bool isRosBag(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[9] = {};
  return in.read(magic, 9) && std::string(magic, 9) == "#ROSBAG V";
}

Sequence readRosBag(const std::string& path, const ReadOptions& options) {
  const BagTopicMap map = options.bag_topics.empty() ? BagTopicMap{} : readBagTopicMap(options.bag_topics);
  std::vector<Stream> streams = {
      {Role::kImu, "imu", map.imu, {"sensor_msgs/Imu"}},
      {Role::kCamera, "camera", map.camera, {"sensor_msgs/Image", "sensor_msgs/CompressedImage"}},
      {Role::kRotor, "rotor_speeds", map.rotor_speeds, {"mav_msgs/Actuators"}},
      {Role::kThrust, "thrust", map.thrust, {"geometry_msgs/Vector3Stamped", "agiros_msgs/Command"}},
      {Role::kGroundTruth, "groundtruth", map.groundtruth,
       {"geometry_msgs/PoseStamped", "geometry_msgs/TransformStamped", "nav_msgs/Odometry"}}};
  std::map<std::string, const Stream*> by_topic;
  for (const Stream& s : streams) {
    if (s.topic.empty()) continue;
    if (!by_topic.emplace(s.topic, &s).second)
      throw InputError(options.bag_topics, 0, "topic " + s.topic + " is mapped to two streams");
  }

  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open bag");
  std::vector<Pending<ImuSample>> imu;
  std::vector<Pending<BagImage>> cams;
  std::vector<Pending<RotorSample>> rotor;
  std::vector<Pending<ThrustSample>> thrust;
  std::vector<Pending<GroundTruthState>> groundtruth;
  std::map<std::string, std::size_t> counts;
  const bag::BagContents bag = bag::scanBag(in, path, [&](const bag::Message& msg) {
    const auto it = by_topic.find(msg.connection->topic);
    if (it == by_topic.end()) return;
    const Stream& s = *it->second;
    const std::string& type = msg.connection->type;
    if (std::find(s.types.begin(), s.types.end(), type) == s.types.end())
      throw InputError(path, 0, "topic " + s.topic + " (" + s.key + ") has type " + type + ", expected " + joined(s.types));
    ros::MessageCursor m(msg.data, path, s.topic + " message " + std::to_string(++counts[s.topic]));
    const std::string bytes(msg.data);
    switch (s.role) {
      case Role::kImu: imu.push_back({msg.record_time, ros::decodeImu(m), bytes}); break;
      case Role::kRotor: rotor.push_back({msg.record_time, ros::decodeActuators(m), bytes}); break;
      case Role::kThrust:
        thrust.push_back({msg.record_time,
                          type == "agiros_msgs/Command" ? ros::decodeAgirosCommand(m, map.thrust_axis)
                                                        : ros::decodeVector3Stamped(m),
                          bytes});
        break;
      case Role::kGroundTruth: groundtruth.push_back({msg.record_time, ros::decodePose(m, type), bytes}); break;
      case Role::kCamera: {
        ContainerSpan span = msg.span;
        span.compressed_image = type == "sensor_msgs/CompressedImage";
        const ros::ImageHeader h = ros::decodeImageHeader(m, span.compressed_image);
        cams.push_back({msg.record_time, BagImage{h.t, h, span}, ""});  // pixels stay in the bag
        break;
      }
    }
  });

  // Every stream the map names (and the IMU) must be in the bag, with an accepted type even
  // when it holds no messages.
  std::vector<std::string> topics;
  std::map<std::string, std::string> type_of;
  for (const auto& [id, c] : bag.connections) {
    topics.push_back(c.topic + " (" + c.type + ")");
    type_of[c.topic] = c.type;
  }
  for (const Stream& s : streams) {
    if (s.topic.empty()) continue;
    const auto t = type_of.find(s.topic);
    if (t == type_of.end()) {
      if (s.role == Role::kImu || map.named.count(s.key))
        throw InputError(path, 0, "missing topic " + s.topic + " (" + s.key + "); the bag holds: " + joined(topics));
      continue;
    }
    if (std::find(s.types.begin(), s.types.end(), t->second) == s.types.end())
      throw InputError(path, 0, "topic " + s.topic + " (" + s.key + ") has type " + t->second + ", expected " + joined(s.types));
  }
  if (imu.empty()) throw InputError(path, 0, "no IMU messages on " + map.imu);

  Sequence seq;
  const fs::path canonical = fs::weakly_canonical(fs::absolute(path));
  seq.source = canonical.string();
  seq.name = canonical.stem().string();
  const CalibrationExtras extras = readCalibration(options.calibration, !cams.empty(), &seq);

  emit(&imu, path, map.imu, &seq, [&](const ImuSample& s, std::size_t i) {
    if (!seq.imu.empty()) {
      try {
        checkImuGap(seq.imu.back().t, s.t, options.max_imu_gap_s, path, 0);
      } catch (const InputError& e) {
        throw InputError(path, 0, map.imu + " message " + std::to_string(i + 1) + ": " + e.problem());
      }
    }
    seq.imu.push_back(s);
  });
  emit(&cams, path, map.camera, &seq, [&](const BagImage& l, std::size_t i) {
    const CameraCalibration& c = *seq.camera;
    if (l.header.width > 0 && (l.header.width != c.width || l.header.height != c.height))
      throw InputError(path, 0, map.camera + " message " + std::to_string(i + 1) + ": image " +
                                    std::to_string(l.header.width) + "x" + std::to_string(l.header.height) +
                                    " does not match the calibration " + std::to_string(c.width) + "x" +
                                    std::to_string(c.height) + " (" + c.file + ")");
    seq.images.push_back(ImageRef{l.t, seq.source, l.span, {}, 0});
  });
  emit(&rotor, path, map.rotor_speeds, &seq, [&](const RotorSample& s, std::size_t) { seq.rotor.push_back(s); });
  emit(&thrust, path, map.thrust, &seq, [&](const ThrustSample& s, std::size_t) { seq.thrust.push_back(s); });
  emit(&groundtruth, path, map.groundtruth, &seq,
       [&](const GroundTruthState& s, std::size_t) { seq.groundtruth.push_back(s); });

  applyCalibrationExtras(extras, path, &seq);
  applyRotorOptions(options, path, &seq);
  return seq;
}

}  // namespace hdvio::io
