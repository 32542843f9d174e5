// Fuzzes the ROS message deserialization (ros_messages.cc) directly: the first byte picks the
// message type, the rest is the serialized message (what a bag's message record holds).
#include <cstdint>
#include <string>

#include "fuzz_common.h"
#include "hdvio/core/error.h"
#include "ros_messages.h"

using namespace hdvio;
using namespace hdvio::io;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string bytes = fuzz::bytesOf(data + 1, size - 1);
  // MessageCursor keeps a reference to the file name: it must outlive the cursor.
  static const std::string file = "fuzz.bag";
  ros::MessageCursor m(bytes, file, "/topic message 1");
  try {
    switch (data[0] % 10) {
      case 0: (void)ros::decodeImu(m); break;
      case 1: (void)ros::decodeActuators(m); break;
      case 2: (void)ros::decodeVector3Stamped(m); break;
      case 3: (void)ros::decodeAgirosCommand(m, Vec3::UnitZ()); break;
      case 4: (void)ros::decodePose(m, "geometry_msgs/PoseStamped"); break;
      case 5: (void)ros::decodePose(m, "geometry_msgs/TransformStamped"); break;
      case 6: (void)ros::decodePose(m, "nav_msgs/Odometry"); break;
      case 7: (void)ros::decodeImageHeader(m, data[0] & 0x80); break;
      case 8: (void)ros::decodeImagePixels(bytes, false, file, "/cam0 message 1"); break;
      case 9: (void)ros::decodeImagePixels(bytes, true, file, "/cam0 message 1"); break;
    }
  } catch (const InputError&) {
  }
  return 0;
}
