#include "bag_format.h"

#include <cstring>
#include <vector>

#include "bag_compression.h"
#include "hdvio/core/error.h"

namespace hdvio::io::bag {
namespace {

constexpr std::string_view kMagic = "#ROSBAG V2.0\n";
constexpr std::uint8_t kOpMessage = 0x02, kOpBagHeader = 0x03, kOpIndex = 0x04, kOpChunk = 0x05,
                       kOpChunkInfo = 0x06, kOpConnection = 0x07;

std::string at(std::uint64_t pos) { return "record at byte " + std::to_string(pos); }

std::uint32_t le32(const char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);  // the format is little-endian, as is every platform hdvio runs on
  return v;
}

// The name=value fields of a record header (or of a connection record's data).
class Fields {
 public:
  Fields(std::string_view bytes, const std::string& name, std::uint64_t pos) : name_(name), pos_(pos) {
    std::size_t i = 0;
    while (i < bytes.size()) {
      if (bytes.size() - i < 4) fail("header field length runs past the header");
      const std::uint32_t len = le32(bytes.data() + i);
      i += 4;
      if (len > bytes.size() - i) fail("header field of " + std::to_string(len) + " bytes runs past the header");
      const std::string_view field = bytes.substr(i, len);
      i += len;
      const std::size_t eq = field.find('=');
      if (eq == std::string_view::npos) fail("header field without '='");
      fields_.emplace(std::string(field.substr(0, eq)), std::string(field.substr(eq + 1)));
    }
  }

  bool has(const std::string& key) const { return fields_.count(key) > 0; }
  const std::string& bytes(const std::string& key) const {
    const auto it = fields_.find(key);
    if (it == fields_.end()) fail("missing header field '" + key + "'");
    return it->second;
  }
  std::uint8_t op() const { return static_cast<std::uint8_t>(sized("op", 1)[0]); }
  std::uint32_t u32(const std::string& key) const { return le32(sized(key, 4).data()); }
  std::uint64_t u64(const std::string& key) const {
    const std::string& v = sized(key, 8);
    return le32(v.data()) | (static_cast<std::uint64_t>(le32(v.data() + 4)) << 32);
  }
  Timestamp time(const std::string& key) const {
    const std::string& v = sized(key, 8);
    const std::uint32_t nsec = le32(v.data() + 4);
    if (nsec >= 1000000000u) fail("field '" + key + "' has " + std::to_string(nsec) + " nanoseconds");
    return rosTime(le32(v.data()), nsec);
  }
  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(name_, 0, at(pos_) + ": " + problem);
  }

 private:
  const std::string& sized(const std::string& key, std::size_t n) const {
    const std::string& v = bytes(key);
    if (v.size() != n)
      fail("field '" + key + "' has " + std::to_string(v.size()) + " bytes, expected " + std::to_string(n));
    return v;
  }
  const std::string& name_;
  std::uint64_t pos_;
  std::map<std::string, std::string> fields_;
};

struct Record {
  std::uint64_t pos = 0;        // of the record's first byte
  std::uint64_t data_pos = 0;   // of its data
  std::string header;
  std::string data;
};

// One record from the stream; `end` is the stream size (lengths are checked against it before
// anything is allocated). Returns false at a clean end of file.
bool readRecord(std::istream& in, std::uint64_t end, const std::string& name, Record* r) {
  r->pos = static_cast<std::uint64_t>(in.tellg());
  if (r->pos == end) return false;
  auto read_block = [&](std::string* out, const char* what) {
    const std::uint64_t pos = static_cast<std::uint64_t>(in.tellg());
    char len_bytes[4];
    if (end - pos < 4 || !in.read(len_bytes, 4))
      throw InputError(name, 0, "truncated bag: " + at(r->pos) + " ends inside its " + what + " length");
    const std::uint32_t len = le32(len_bytes);
    if (len > end - pos - 4)
      throw InputError(name, 0, "truncated bag: " + at(r->pos) + " declares a " + what + " of " +
                                    std::to_string(len) + " bytes, past the end of the file");
    out->resize(len);
    if (len > 0 && !in.read(out->data(), len))
      throw InputError(name, 0, "cannot read " + at(r->pos));
  };
  read_block(&r->header, "header");
  r->data_pos = static_cast<std::uint64_t>(in.tellg()) + 4;
  read_block(&r->data, "data");
  return true;
}

// The records of a chunk's uncompressed data: (header, data, offset of data) triples.
template <class Visit>
void forEachInChunk(std::string_view chunk, const std::string& name, std::uint64_t chunk_pos, Visit visit) {
  std::size_t i = 0;
  auto block = [&](std::string_view* out, const char* what) {
    if (chunk.size() - i < 4)
      throw InputError(name, 0, "chunk " + at(chunk_pos) + ": inner record " + what + " length runs past the chunk");
    const std::uint32_t len = le32(chunk.data() + i);
    i += 4;
    if (len > chunk.size() - i)
      throw InputError(name, 0, "chunk " + at(chunk_pos) + ": inner record " + what + " runs past the chunk");
    *out = chunk.substr(i, len);
    i += len;
  };
  while (i < chunk.size()) {
    std::string_view header, data;
    block(&header, "header");
    const std::size_t data_offset = i + 4;
    block(&data, "data");
    visit(header, data, data_offset);
  }
}

Connection connectionFrom(const Fields& h, std::string_view data, const std::string& name, std::uint64_t pos) {
  const Fields c(data, name, pos);
  Connection conn;
  conn.id = h.u32("conn");
  conn.topic = h.bytes("topic");
  conn.type = c.bytes("type");
  conn.md5sum = c.has("md5sum") ? c.bytes("md5sum") : "";
  return conn;
}

void addConnection(BagContents* bag, Connection conn, const Fields& h) {
  const auto [it, inserted] = bag->connections.emplace(conn.id, conn);
  if (!inserted && (it->second.topic != conn.topic || it->second.type != conn.type))
    h.fail("connection " + std::to_string(conn.id) + " redefined (" + it->second.topic + " " +
           it->second.type + " -> " + conn.topic + " " + conn.type + ")");
}

}  // namespace

Timestamp rosTime(std::uint32_t sec, std::uint32_t nsec) {
  return static_cast<Timestamp>(sec) * kNanosPerSecond + static_cast<Timestamp>(nsec);
}

BagContents scanBag(std::istream& in, const std::string& name,
                    const std::function<void(const Message&)>& visit) {
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (!in || size < 0) throw InputError(name, 0, "cannot read file");
  const std::uint64_t end = static_cast<std::uint64_t>(size);
  in.seekg(0);
  std::string magic(kMagic.size(), '\0');
  if (end < kMagic.size() || !in.read(magic.data(), kMagic.size()) || magic.compare(0, 9, "#ROSBAG V") != 0)
    throw InputError(name, 0, "not a ROS bag (no '#ROSBAG V' magic at the start)");
  if (magic != kMagic)
    throw InputError(name, 0, "unsupported bag version '" + magic.substr(9, magic.find('\n') - 9) +
                                  "' (only ROS 1 bag format V2.0 is read)");

  Record r;
  if (!readRecord(in, end, name, &r)) throw InputError(name, 0, "truncated bag: no bag header record");
  const Fields bag_header(r.header, name, r.pos);
  if (bag_header.op() != kOpBagHeader) bag_header.fail("expected the bag header record (op 0x03)");
  const std::uint64_t index_pos = bag_header.u64("index_pos");
  const std::uint32_t conn_count = bag_header.u32("conn_count");
  const std::uint32_t chunk_count = bag_header.u32("chunk_count");
  if (index_pos == 0)
    throw InputError(name, 0, "bag is not indexed (the recording was not closed; 'rosbag reindex' repairs it)");
  if (index_pos >= end)
    throw InputError(name, 0, "truncated bag: the index starts at byte " + std::to_string(index_pos) +
                                  " but the file has " + std::to_string(end) + " bytes");

  BagContents bag;
  std::size_t chunk_infos = 0;
  std::string chunk;
  while (readRecord(in, end, name, &r)) {
    const Fields h(r.header, name, r.pos);
    switch (h.op()) {
      case kOpChunk: {
        if (r.pos >= index_pos) h.fail("chunk inside the index section");
        ++bag.chunks;
        const std::string compression = h.bytes("compression");
        decompressChunk(compression, r.data, h.u32("size"), name, r.pos, &chunk);
        const bool compressed = compression != "none";
        forEachInChunk(chunk, name, r.pos, [&](std::string_view header, std::string_view data, std::size_t offset) {
          const std::uint64_t inner_pos = compressed ? r.pos : r.data_pos + offset - 8 - header.size();
          const Fields ih(header, name, inner_pos);
          if (ih.op() == kOpConnection) {
            addConnection(&bag, connectionFrom(ih, data, name, inner_pos), ih);
          } else if (ih.op() == kOpMessage) {
            const auto it = bag.connections.find(ih.u32("conn"));
            if (it == bag.connections.end())
              ih.fail("message of connection " + std::to_string(ih.u32("conn")) + " before its connection record");
            Message m;
            m.connection = &it->second;
            m.record_time = ih.time("time");
            m.data = data;
            m.span = ContainerSpan{r.pos, offset, data.size(), false};
            ++bag.messages;
            visit(m);
          } else {
            ih.fail("unexpected record op " + std::to_string(ih.op()) + " inside a chunk");
          }
        });
        break;
      }
      case kOpIndex:
        if (h.u32("ver") != 1) h.fail("unsupported index data version");
        if (r.data.size() != 12ull * h.u32("count")) h.fail("index data size does not match its count");
        break;
      case kOpConnection:
        if (r.pos < index_pos) h.fail("connection record outside chunks before the index");
        addConnection(&bag, connectionFrom(h, r.data, name, r.pos), h);
        break;
      case kOpChunkInfo:
        if (h.u32("ver") != 1) h.fail("unsupported chunk info version");
        if (r.data.size() != 8ull * h.u32("count")) h.fail("chunk info size does not match its count");
        ++chunk_infos;
        break;
      default:
        h.fail("unexpected record op " + std::to_string(h.op()));
    }
  }
  if (bag.chunks != chunk_count || chunk_infos != chunk_count || bag.connections.size() != conn_count)
    throw InputError(name, 0, "truncated or inconsistent bag: the header announces " +
                                  std::to_string(chunk_count) + " chunks and " + std::to_string(conn_count) +
                                  " connections, the file holds " + std::to_string(bag.chunks) + " chunks, " +
                                  std::to_string(chunk_infos) + " chunk infos and " +
                                  std::to_string(bag.connections.size()) + " connections");
  return bag;
}

std::string readMessage(std::istream& in, const ContainerSpan& span, const std::string& name) {
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (!in || size < 0 || span.chunk_pos >= static_cast<std::uint64_t>(size))
    throw InputError(name, 0, "cannot read chunk at byte " + std::to_string(span.chunk_pos));
  in.seekg(static_cast<std::streamoff>(span.chunk_pos));
  Record r;
  if (!readRecord(in, static_cast<std::uint64_t>(size), name, &r))
    throw InputError(name, 0, "no chunk at byte " + std::to_string(span.chunk_pos));
  const Fields h(r.header, name, r.pos);
  if (h.op() != kOpChunk) h.fail("expected a chunk record");
  std::string chunk;
  decompressChunk(h.bytes("compression"), r.data, h.u32("size"), name, r.pos, &chunk);
  if (span.offset > chunk.size() || span.size > chunk.size() - span.offset)
    h.fail("message span lies outside the chunk");
  return chunk.substr(span.offset, span.size);
}

}  // namespace hdvio::io::bag
