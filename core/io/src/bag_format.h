#pragma once
// The ROS 1 bag format v2.0 (wiki.ros.org/Bags/Format/2.0) at the level of records: magic,
// bag header, chunks (none / bz2 / lz4), connections, message data, index and chunk info.
// Everything here is a pure function of the bytes of a std::istream (a file or a string
// buffer) so that it can be fuzzed; every problem is an InputError naming `name` and a byte
// offset. The index records are checked for shape but not used: messages are taken from the
// chunks in file order and the caller orders them.
#include <cstdint>
#include <functional>
#include <istream>
#include <map>
#include <string>
#include <string_view>

#include "hdvio/core/sequence.h"

namespace hdvio::io::bag {

struct Connection {
  std::uint32_t id = 0;
  std::string topic;
  std::string type;    // e.g. "sensor_msgs/Imu"
  std::string md5sum;
};

struct Message {
  const Connection* connection = nullptr;
  Timestamp record_time = 0;  // the record's time field (when the recorder received it)
  std::string_view data;      // the serialized message; valid during the callback only
  ContainerSpan span;         // where the bytes lie, for loading them again later
};

struct BagContents {
  std::map<std::uint32_t, Connection> connections;
  std::size_t chunks = 0;
  std::size_t messages = 0;
};

// Reads every record and calls visit() for each message data record, in file order.
// Throws InputError on a bad magic or version, a truncated or malformed record, an unknown
// compression, a message of an unknown connection, or counts that disagree with the header.
BagContents scanBag(std::istream& in, const std::string& name,
                    const std::function<void(const Message&)>& visit);

// The bytes of one message found by scanBag (decompressing its chunk when needed).
std::string readMessage(std::istream& in, const ContainerSpan& span, const std::string& name);

// "sec.nsec" record time field (two little-endian uint32) in nanoseconds.
Timestamp rosTime(std::uint32_t sec, std::uint32_t nsec);

}  // namespace hdvio::io::bag
