#pragma once
// Deserialization of the few ROS 1 message types hdvio reads from bags (little-endian ROS
// serialization: fixed-size fields in order, strings and variable arrays with a uint32 length).
// A message must be consumed exactly: a short or long message is an error, which catches a
// topic whose type name matches but whose definition does not. Sample times are header stamps.
#include <cstdint>
#include <string>
#include <string_view>

#include <opencv2/core.hpp>

#include "hdvio/core/sequence.h"

namespace hdvio::io::ros {

// Reads fields in order; every error names `context` (bag file) and `where` (topic, message).
class MessageCursor {
 public:
  MessageCursor(std::string_view data, const std::string& file, std::string where)
      : data_(data), file_(file), where_(std::move(where)) {}

  std::uint8_t u8();
  std::uint32_t u32();
  double f64();
  std::string_view string();
  std::string_view bytes(std::size_t n);
  Timestamp header();  // std_msgs/Header: seq, stamp, frame_id -> the stamp
  Vec3 vec3();         // geometry_msgs/Vector3 or Point
  Quat quaternion();   // geometry_msgs/Quaternion (x, y, z, w), checked to be unit
  std::size_t position() const { return pos_; }
  void finish() const;  // throws unless every byte was read
  [[noreturn]] void fail(const std::string& problem) const;

 private:
  std::string_view data_;
  std::size_t pos_ = 0;
  const std::string& file_;
  std::string where_;
};

ImuSample decodeImu(MessageCursor& m);                        // sensor_msgs/Imu
RotorSample decodeActuators(MessageCursor& m);                // mav_msgs/Actuators angular_velocities
ThrustSample decodeVector3Stamped(MessageCursor& m);          // geometry_msgs/Vector3Stamped
ThrustSample decodeAgirosCommand(MessageCursor& m, const Vec3& thrust_axis);  // agiros_msgs/Command
// geometry_msgs/PoseStamped, geometry_msgs/TransformStamped or nav_msgs/Odometry (whose twist,
// by the nav_msgs convention, is in the child (body) frame and is rotated into the world).
GroundTruthState decodePose(MessageCursor& m, const std::string& type);

// sensor_msgs/Image without its pixels (checked for size and encoding), or CompressedImage.
struct ImageHeader {
  Timestamp t = 0;
  int width = 0, height = 0;  // 0 for compressed images (known only once decoded)
  std::string encoding;       // mono8 / bgr8 / rgb8, or the compressed format
  std::size_t step = 0;
  std::size_t pixels_offset = 0, pixels_size = 0;  // into the message bytes
};
ImageHeader decodeImageHeader(MessageCursor& m, bool compressed);

// Grayscale 8-bit pixels of a whole image message.
cv::Mat decodeImagePixels(std::string_view message, bool compressed, const std::string& file,
                          const std::string& where);

}  // namespace hdvio::io::ros
