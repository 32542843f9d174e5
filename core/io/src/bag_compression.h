#pragma once
// Chunk (de)compression of ROS 1 bags: "none", "bz2" (libbz2) and "lz4" (the LZ4 frame format,
// which is what roslz4 writes). Compression is only needed by the tests' bag writer.
#include <cstdint>
#include <string>
#include <string_view>

namespace hdvio::io::bag {

// Decompresses a chunk's data into *out, which must then hold exactly `size` bytes. Errors
// name the bag and the chunk's byte offset.
void decompressChunk(const std::string& compression, std::string_view data, std::uint32_t size,
                     const std::string& name, std::uint64_t chunk_pos, std::string* out);

std::string compressChunk(const std::string& compression, std::string_view data);

}  // namespace hdvio::io::bag
