#include "bag_compression.h"

#include <bzlib.h>
#include <lz4frame.h>

#include <algorithm>
#include <memory>
#include <stdexcept>

#include "hdvio/core/error.h"

namespace hdvio::io::bag {
namespace {

void lz4Decompress(std::string_view data, std::string* out, const std::string& fail_prefix,
                   const std::string& name) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)))
    throw std::runtime_error("cannot create an LZ4 decompression context");
  const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(raw, LZ4F_freeDecompressionContext);
  std::size_t in_pos = 0, out_pos = 0;
  std::size_t hint = 1;
  while (in_pos < data.size() && hint != 0) {
    std::size_t out_size = out->size() - out_pos;
    std::size_t in_size = data.size() - in_pos;
    hint = LZ4F_decompress(ctx.get(), out->data() + out_pos, &out_size, data.data() + in_pos, &in_size, nullptr);
    if (LZ4F_isError(hint)) throw InputError(name, 0, fail_prefix + LZ4F_getErrorName(hint));
    in_pos += in_size;
    out_pos += out_size;
    if (out_size == 0 && in_size == 0) break;  // output full but the frame wants more room
  }
  if (hint != 0) throw InputError(name, 0, fail_prefix + "truncated LZ4 frame or more data than the chunk size");
  out->resize(out_pos);
}

// Decompresses in steps of 1 MiB so that memory follows the real output, not the declared
// size: a few bytes of bag could otherwise make the reader allocate 1 GiB.
void bz2Decompress(std::string_view data, std::uint32_t size, std::string* out, const std::string& fail_prefix,
                   const std::string& name) {
  bz_stream s{};
  if (BZ2_bzDecompressInit(&s, 0, 0) != BZ_OK) throw std::runtime_error("cannot create a bz2 decompression stream");
  const std::unique_ptr<bz_stream, int (*)(bz_stream*)> end(&s, BZ2_bzDecompressEnd);
  s.next_in = const_cast<char*>(data.data());
  s.avail_in = static_cast<unsigned int>(data.size());
  out->clear();
  int rc = BZ_OK;
  while (rc == BZ_OK && out->size() <= size) {
    const std::size_t have = out->size();
    const std::size_t step = std::min<std::size_t>(1u << 20, size - have + 1);  // + 1: sees excess data
    out->resize(have + step);
    s.next_out = out->data() + have;
    s.avail_out = static_cast<unsigned int>(step);
    rc = BZ2_bzDecompress(&s);
    out->resize(have + step - s.avail_out);
    if (rc == BZ_OK && s.avail_in == 0 && s.avail_out > 0) rc = BZ_UNEXPECTED_EOF;
  }
  if (rc != BZ_STREAM_END && rc != BZ_OK)
    throw InputError(name, 0, fail_prefix + "bz2 data cannot be decompressed (error " + std::to_string(rc) + ")");
}

}  // namespace

void decompressChunk(const std::string& compression, std::string_view data, std::uint32_t size,
                     const std::string& name, std::uint64_t chunk_pos, std::string* out) {
  const std::string prefix = "chunk at byte " + std::to_string(chunk_pos) + ": ";
  // rosbag writes 768 KiB chunks by default; a larger size than this is corruption, and would
  // otherwise be allocated before decompressing.
  constexpr std::uint32_t kMaxChunkBytes = 1u << 30;
  if (size > kMaxChunkBytes)
    throw InputError(name, 0, prefix + "declares " + std::to_string(size) + " uncompressed bytes (more than 1 GiB)");
  if (compression == "none") {
    out->assign(data);
  } else if (compression == "bz2") {
    bz2Decompress(data, size, out, prefix, name);
  } else if (compression == "lz4") {
    // An LZ4 sequence expands to at most 255 bytes per input byte; more is corruption.
    if (size > 255ull * data.size() + 4096)
      throw InputError(name, 0, prefix + "declares " + std::to_string(size) + " uncompressed bytes from " +
                                    std::to_string(data.size()) + " bytes of lz4 data");
    out->resize(size);
    lz4Decompress(data, out, prefix + "lz4: ", name);
  } else {
    throw InputError(name, 0, prefix + "unsupported chunk compression '" + compression + "' (none, bz2 and lz4 are read)");
  }
  if (out->size() != size)
    throw InputError(name, 0, prefix + "holds " + std::to_string(out->size()) + " bytes, its header says " +
                                  std::to_string(size));
}

std::string compressChunk(const std::string& compression, std::string_view data) {
  if (compression == "none") return std::string(data);
  if (compression == "bz2") {
    unsigned int len = static_cast<unsigned int>(data.size() + data.size() / 100 + 600);
    std::string out(len, '\0');
    if (BZ2_bzBuffToBuffCompress(out.data(), &len, const_cast<char*>(data.data()),
                                 static_cast<unsigned int>(data.size()), 9, 0, 0) != BZ_OK)
      throw std::runtime_error("bz2 compression failed");
    out.resize(len);
    return out;
  }
  if (compression == "lz4") {
    std::string out(LZ4F_compressFrameBound(data.size(), nullptr), '\0');
    const std::size_t len = LZ4F_compressFrame(out.data(), out.size(), data.data(), data.size(), nullptr);
    if (LZ4F_isError(len)) throw std::runtime_error("lz4 compression failed");
    out.resize(len);
    return out;
  }
  throw std::invalid_argument("unknown compression " + compression);
}

}  // namespace hdvio::io::bag
