#pragma once
// A small ROS 1 bag (format 2.0) writer for the tests, independent of the reader: records laid
// out as rosbag does (bag header padded to 4096 bytes, chunks holding connection and message
// records, index data after each chunk, connections and chunk infos in the index section), plus
// ROS serialization of the message types hdvio reads.
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "bag_compression.h"
#include "hdvio/core/sequence.h"

namespace hdvio::io::test {

// Little-endian ROS serialization.
class RosBytes {
 public:
  RosBytes& u8(std::uint8_t v) { return raw(&v, 1); }
  RosBytes& u32(std::uint32_t v) { return raw(&v, 4); }
  RosBytes& u64(std::uint64_t v) { return raw(&v, 8); }
  RosBytes& f64(double v) { return raw(&v, 8); }
  RosBytes& str(const std::string& s) { return u32(static_cast<std::uint32_t>(s.size())).raw(s.data(), s.size()); }
  RosBytes& time(Timestamp t) {
    return u32(static_cast<std::uint32_t>(t / kNanosPerSecond)).u32(static_cast<std::uint32_t>(t % kNanosPerSecond));
  }
  RosBytes& header(Timestamp stamp, std::uint32_t seq = 0) { return u32(seq).time(stamp).str("world"); }
  RosBytes& vec3(const Vec3& v) { return f64(v.x()).f64(v.y()).f64(v.z()); }
  RosBytes& quat(const Quat& q) { return f64(q.x()).f64(q.y()).f64(q.z()).f64(q.w()); }
  RosBytes& zeros(std::size_t n_doubles) {
    for (std::size_t i = 0; i < n_doubles; ++i) f64(0.0);
    return *this;
  }
  RosBytes& raw(const void* p, std::size_t n) {
    bytes_.append(static_cast<const char*>(p), n);
    return *this;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

inline std::string imuMessage(const ImuSample& s) {
  return RosBytes().header(s.t).quat(Quat::Identity()).zeros(9).vec3(s.gyro).zeros(9).vec3(s.accel).zeros(9).bytes();
}
inline std::string imageMessage(Timestamp t, const cv::Mat& pixels, const std::string& encoding) {
  RosBytes b;
  const std::size_t step = pixels.cols * pixels.elemSize();
  b.header(t).u32(pixels.rows).u32(pixels.cols).str(encoding).u8(0).u32(static_cast<std::uint32_t>(step));
  b.u32(static_cast<std::uint32_t>(step * pixels.rows));
  for (int r = 0; r < pixels.rows; ++r) b.raw(pixels.ptr(r), step);
  return b.bytes();
}
inline std::string compressedImageMessage(Timestamp t, const std::vector<unsigned char>& png) {
  return RosBytes().header(t).str("png").u32(static_cast<std::uint32_t>(png.size())).raw(png.data(), png.size()).bytes();
}
inline std::string actuatorsMessage(const RotorSample& s) {
  RosBytes b;
  b.header(s.t).u32(0).u32(4);
  for (int i = 0; i < 4; ++i) b.f64(s.speeds[i]);
  return b.u32(0).bytes();
}
inline std::string vector3StampedMessage(const ThrustSample& s) { return RosBytes().header(s.t).vec3(s.thrust).bytes(); }
inline std::string agirosCommandMessage(Timestamp t, double collective, bool single_rotor = false) {
  return RosBytes().header(t).f64(1e-9 * t).u8(single_rotor).f64(collective).vec3(Vec3(0.1, 0.2, 0.3)).zeros(4).bytes();
}
inline std::string poseStampedMessage(const GroundTruthState& s) {
  return RosBytes().header(s.t).vec3(s.T_WB.p).quat(s.T_WB.q).bytes();
}
inline std::string transformStampedMessage(const GroundTruthState& s) {
  return RosBytes().header(s.t).str("body").vec3(s.T_WB.p).quat(s.T_WB.q).bytes();
}
inline std::string odometryMessage(const GroundTruthState& s, const Vec3& v_body) {
  return RosBytes().header(s.t).str("body").vec3(s.T_WB.p).quat(s.T_WB.q).zeros(36).vec3(v_body).vec3(Vec3::Zero()).zeros(36).bytes();
}

class BagWriter {
 public:
  // Messages go into chunks of about chunk_bytes (uncompressed), compressed as given.
  explicit BagWriter(std::string compression = "none", std::size_t chunk_bytes = 64 * 1024)
      : compression_(std::move(compression)), chunk_bytes_(chunk_bytes) {}

  std::uint32_t connection(const std::string& topic, const std::string& type) {
    const auto id = static_cast<std::uint32_t>(connections_.size());
    connections_.push_back({topic, type});
    return id;
  }

  void write(std::uint32_t conn, Timestamp record_time, const std::string& message) {
    if (!written_.count(conn)) {
      written_[conn] = true;
      chunk_ += connectionRecord(conn);
    }
    index_[conn].push_back({record_time, static_cast<std::uint32_t>(chunk_.size())});
    chunk_ += record(fields({{"op", byte(0x02)}, {"conn", u32(conn)}, {"time", time(record_time)}}), message);
    start_ = chunk_start_set_ ? std::min(start_, record_time) : record_time;
    end_ = chunk_start_set_ ? std::max(end_, record_time) : record_time;
    chunk_start_set_ = true;
    if (chunk_.size() >= chunk_bytes_) flushChunk();
  }

  // The whole bag. announce_* let a test write a header that disagrees with the body.
  std::string finish() {
    flushChunk();
    const std::uint64_t index_pos = 13 + 4096 + body_.size();
    std::string index;
    for (std::uint32_t c = 0; c < connections_.size(); ++c) index += connectionRecord(c);
    for (const ChunkInfo& ci : infos_) {
      std::string data;
      for (const auto& [conn, count] : ci.counts) data += u32(conn) + u32(count);
      index += record(fields({{"op", byte(0x06)}, {"ver", u32(1)}, {"chunk_pos", u64(ci.pos)},
                              {"start_time", time(ci.start)}, {"end_time", time(ci.end)},
                              {"count", u32(static_cast<std::uint32_t>(ci.counts.size()))}}),
                      data);
    }
    const std::string header = fields({{"op", byte(0x03)}, {"index_pos", u64(unindexed ? 0 : index_pos)},
                                       {"conn_count", u32(static_cast<std::uint32_t>(connections_.size()))},
                                       {"chunk_count", u32(static_cast<std::uint32_t>(infos_.size()))}});
    std::string bag = "#ROSBAG V2.0\n" + record(header, std::string(4096 - 8 - header.size(), ' '));
    return bag + body_ + index;
  }

  bool unindexed = false;

 private:
  struct ChunkInfo {
    std::uint64_t pos;
    Timestamp start, end;
    std::map<std::uint32_t, std::uint32_t> counts;
  };
  struct Entry {
    Timestamp t;
    std::uint32_t offset;
  };

  static std::string byte(std::uint8_t v) { return std::string(1, static_cast<char>(v)); }
  static std::string u32(std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }
  static std::string u64(std::uint64_t v) { return std::string(reinterpret_cast<const char*>(&v), 8); }
  static std::string time(Timestamp t) {
    return u32(static_cast<std::uint32_t>(t / kNanosPerSecond)) + u32(static_cast<std::uint32_t>(t % kNanosPerSecond));
  }
  static std::string fields(const std::vector<std::pair<std::string, std::string>>& kv) {
    std::string s;
    for (const auto& [k, v] : kv) s += u32(static_cast<std::uint32_t>(k.size() + 1 + v.size())) + k + "=" + v;
    return s;
  }
  static std::string record(const std::string& header, const std::string& data) {
    return u32(static_cast<std::uint32_t>(header.size())) + header + u32(static_cast<std::uint32_t>(data.size())) + data;
  }
  std::string connectionRecord(std::uint32_t conn) const {
    const auto& [topic, type] = connections_[conn];
    return record(fields({{"op", byte(0x07)}, {"conn", u32(conn)}, {"topic", topic}}),
                  fields({{"topic", topic}, {"type", type}, {"md5sum", "*"}, {"message_definition", ""}}));
  }
  void flushChunk() {
    if (chunk_.empty()) return;
    ChunkInfo ci{13 + 4096 + body_.size(), start_, end_, {}};
    body_ += record(fields({{"op", byte(0x05)}, {"compression", compression_},
                            {"size", u32(static_cast<std::uint32_t>(chunk_.size()))}}),
                    bag::compressChunk(compression_, chunk_));
    for (const auto& [conn, entries] : index_) {
      std::string data;
      for (const Entry& e : entries) data += time(e.t) + u32(e.offset);
      body_ += record(fields({{"op", byte(0x04)}, {"ver", u32(1)}, {"conn", u32(conn)},
                              {"count", u32(static_cast<std::uint32_t>(entries.size()))}}),
                      data);
      ci.counts[conn] = static_cast<std::uint32_t>(entries.size());
    }
    infos_.push_back(ci);
    chunk_.clear();
    index_.clear();
    chunk_start_set_ = false;
  }

  std::string compression_;
  std::size_t chunk_bytes_;
  std::vector<std::pair<std::string, std::string>> connections_;
  std::map<std::uint32_t, bool> written_;
  std::string chunk_, body_;
  std::map<std::uint32_t, std::vector<Entry>> index_;
  std::vector<ChunkInfo> infos_;
  Timestamp start_ = 0, end_ = 0;
  bool chunk_start_set_ = false;
};

}  // namespace hdvio::io::test
