#include "ros_messages.h"

#include <cmath>
#include <cstring>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bag_format.h"
#include "hdvio/core/error.h"
#include "stream_checks.h"

namespace hdvio::io::ros {

std::string_view MessageCursor::bytes(std::size_t n) {
  if (n > data_.size() - pos_)
    fail("message ends after " + std::to_string(data_.size()) + " bytes, inside a field (wrong message type?)");
  const std::string_view out = data_.substr(pos_, n);
  pos_ += n;
  return out;
}

std::uint8_t MessageCursor::u8() { return static_cast<std::uint8_t>(bytes(1)[0]); }

std::uint32_t MessageCursor::u32() {
  std::uint32_t v;
  std::memcpy(&v, bytes(4).data(), 4);
  return v;
}

double MessageCursor::f64() {
  double v;
  std::memcpy(&v, bytes(8).data(), 8);
  if (!std::isfinite(v)) fail("non-finite number at byte " + std::to_string(pos_ - 8) + " of the message");
  return v;
}

std::string_view MessageCursor::string() { return bytes(u32()); }

Timestamp MessageCursor::header() {
  u32();  // seq
  const std::uint32_t sec = u32(), nsec = u32();
  if (nsec >= 1000000000u) fail("header stamp has " + std::to_string(nsec) + " nanoseconds");
  string();  // frame_id
  return bag::rosTime(sec, nsec);
}

Vec3 MessageCursor::vec3() {
  const double x = f64(), y = f64(), z = f64();
  return Vec3(x, y, z);
}

Quat MessageCursor::quaternion() {
  const double x = f64(), y = f64(), z = f64(), w = f64();
  try {
    return unitQuaternion(w, x, y, z, file_, 0);
  } catch (const InputError& e) {
    fail(e.problem());
  }
}

void MessageCursor::finish() const {
  if (pos_ != data_.size())
    fail("message has " + std::to_string(data_.size() - pos_) + " bytes left over (wrong message type?)");
}

void MessageCursor::fail(const std::string& problem) const { throw InputError(file_, 0, where_ + ": " + problem); }

ImuSample decodeImu(MessageCursor& m) {
  ImuSample s;
  s.t = m.header();
  m.bytes(4 * 8 + 9 * 8);  // orientation and its covariance
  s.gyro = m.vec3();
  m.bytes(9 * 8);
  s.accel = m.vec3();
  m.bytes(9 * 8);
  m.finish();
  return s;
}

RotorSample decodeActuators(MessageCursor& m) {
  RotorSample s;
  s.t = m.header();
  m.bytes(8 * std::size_t{m.u32()});  // angles
  const std::uint32_t n = m.u32();
  if (n != 4) m.fail("angular_velocities has " + std::to_string(n) + " entries, expected 4 rotors");
  for (int i = 0; i < 4; ++i) s.speeds[i] = m.f64();
  m.bytes(8 * std::size_t{m.u32()});  // normalized
  m.finish();
  return s;
}

ThrustSample decodeVector3Stamped(MessageCursor& m) {
  ThrustSample s;
  s.t = m.header();
  s.thrust = m.vec3();
  m.finish();
  return s;
}

ThrustSample decodeAgirosCommand(MessageCursor& m, const Vec3& thrust_axis) {
  ThrustSample s;
  s.t = m.header();
  m.f64();  // t [s], the controller's own clock
  const bool single_rotor = m.u8() != 0;
  const double collective = m.f64();
  m.vec3();      // bodyrates
  m.bytes(4 * 8);  // single rotor thrusts [N]
  m.finish();
  if (single_rotor) m.fail("single-rotor thrust commands are not supported (collective thrust is read)");
  s.thrust = collective * thrust_axis;
  return s;
}

GroundTruthState decodePose(MessageCursor& m, const std::string& type) {
  GroundTruthState s;
  s.t = m.header();
  if (type == "geometry_msgs/TransformStamped") {
    m.string();  // child_frame_id
    const Vec3 p = m.vec3();
    s.T_WB = poseExact(m.quaternion(), p);
  } else {
    if (type == "nav_msgs/Odometry") m.string();  // child_frame_id
    const Vec3 p = m.vec3();
    s.T_WB = poseExact(m.quaternion(), p);
    if (type == "nav_msgs/Odometry") {
      m.bytes(36 * 8);  // pose covariance
      s.v_W = s.T_WB.q * m.vec3();
      s.has_velocity = true;
      m.vec3();         // angular
      m.bytes(36 * 8);  // twist covariance
    }
  }
  m.finish();
  return s;
}

ImageHeader decodeImageHeader(MessageCursor& m, bool compressed) {
  ImageHeader h;
  h.t = m.header();
  if (compressed) {
    h.encoding = std::string(m.string());
    h.pixels_size = m.u32();
    h.pixels_offset = m.position();
    m.bytes(h.pixels_size);
    m.finish();
    return h;
  }
  const std::uint32_t height = m.u32(), width = m.u32();
  h.encoding = std::string(m.string());
  m.u8();  // is_bigendian: irrelevant for 8-bit encodings
  h.step = m.u32();
  h.pixels_size = m.u32();
  h.pixels_offset = m.position();
  m.bytes(h.pixels_size);
  m.finish();
  const int channels = h.encoding == "mono8" || h.encoding == "8UC1" ? 1 : h.encoding == "bgr8" || h.encoding == "rgb8" ? 3 : 0;
  if (channels == 0) m.fail("unsupported image encoding '" + h.encoding + "' (mono8, bgr8 and rgb8 are read)");
  if (width == 0 || height == 0 || width > 100000 || height > 100000)
    m.fail("image size " + std::to_string(width) + "x" + std::to_string(height) + " is not plausible");
  if (h.step < std::size_t{width} * channels || h.pixels_size != h.step * height)
    m.fail("image data of " + std::to_string(h.pixels_size) + " bytes does not match " + std::to_string(height) +
           " rows of step " + std::to_string(h.step) + " for width " + std::to_string(width) + " " + h.encoding);
  h.width = static_cast<int>(width);
  h.height = static_cast<int>(height);
  return h;
}

cv::Mat decodeImagePixels(std::string_view message, bool compressed, const std::string& file,
                          const std::string& where) {
  MessageCursor m(message, file, where);
  const ImageHeader h = decodeImageHeader(m, compressed);
  const char* pixels = message.data() + h.pixels_offset;
  if (compressed) {
    const cv::Mat buffer(1, static_cast<int>(h.pixels_size), CV_8U, const_cast<char*>(pixels));
    cv::Mat gray;
    try {
      gray = cv::imdecode(buffer, cv::IMREAD_GRAYSCALE);
    } catch (const cv::Exception& e) {
      m.fail(std::string("cannot decode compressed image: ") + e.what());
    }
    if (gray.empty()) m.fail("cannot decode compressed image (format '" + h.encoding + "')");
    return gray;
  }
  const bool mono = h.encoding == "mono8" || h.encoding == "8UC1";
  const cv::Mat view(h.height, h.width, mono ? CV_8UC1 : CV_8UC3, const_cast<char*>(pixels), h.step);
  cv::Mat gray;
  if (mono) gray = view.clone();
  else cv::cvtColor(view, gray, h.encoding == "bgr8" ? cv::COLOR_BGR2GRAY : cv::COLOR_RGB2GRAY);
  return gray;
}

}  // namespace hdvio::io::ros
