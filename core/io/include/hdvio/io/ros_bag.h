#pragma once
// ROS 1 bags (format 2.0) read without ROS: a topic map names which topic feeds which stream,
// a calibration folder (cam0/imu0/rotor0 sensor.yaml) or Kalibr files supply what bags do not carry.
// Sample times are the messages' header stamps. See docs/datasets.md, "ROS bags".
#include <set>
#include <string>

#include "hdvio/core/sequence.h"
#include "hdvio/io/read_options.h"

namespace hdvio::io {

// Topic of each stream; empty: not read. The defaults are EuRoC's topic names.
struct BagTopicMap {
  std::string imu = "/imu0";                                 // sensor_msgs/Imu
  std::string camera = "/cam0/image_raw";                    // sensor_msgs/Image or CompressedImage
  std::string rotor_speeds;                                  // mav_msgs/Actuators (rad/s)
  std::string thrust;                                        // geometry_msgs/Vector3Stamped or agiros_msgs/Command
  Vec3 thrust_axis = Vec3::UnitZ();                          // IMU-frame direction of a collective thrust command
  std::string groundtruth = "/vicon/firefly_sbx/firefly_sbx";  // PoseStamped, TransformStamped or Odometry
  // Streams the map file named explicitly: their topic must be in the bag. A default topic
  // the bag lacks is skipped (except imu, which is always required).
  std::set<std::string> named;
};

// Strict YAML (unknown keys and wrong types are InputErrors): keys imu, camera, rotor_speeds,
// thrust, thrust_axis, groundtruth.
BagTopicMap readBagTopicMap(const std::string& yaml_path);

// True if the file starts with the "#ROSBAG V" magic.
bool isRosBag(const std::string& path);

// Reads the bag with options.bag_topics (a topic-map YAML, or the defaults) and the
// calibration options.calibration (required when the bag holds images). Images stay in
// the bag: ImageRef::span points at their message and loadImage decodes it on demand.
Sequence readRosBag(const std::string& path, const ReadOptions& options = {});

}  // namespace hdvio::io
