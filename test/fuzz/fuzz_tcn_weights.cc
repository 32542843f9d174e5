// Fuzzes the TCN weight file parser (learned/src/tcn_weight_file.cc): the input is the file.
// A file the parser accepts must survive a write/read round trip in both encodings with the
// same weights, bit for bit.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>

#include "fuzz_common.h"
#include "hdvio/core/error.h"
#include "hdvio/learned/tcn_weight_file.h"

using namespace hdvio;
using namespace hdvio::learned;

namespace {

bool same(const MatrixXf& a, const MatrixXf& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         (a.size() == 0 || std::memcmp(a.data(), b.data(), sizeof(float) * a.size()) == 0);
}

bool sameWeights(const TcnWeights& a, const TcnWeights& b) {
  if (a.conv.size() != b.conv.size() || a.skip.size() != b.skip.size()) return false;
  for (std::size_t i = 0; i < a.conv.size(); ++i)
    if (!same(a.conv[i].weight, b.conv[i].weight) || !same(a.conv[i].bias, b.conv[i].bias)) return false;
  for (std::size_t i = 0; i < a.skip.size(); ++i)
    if (!same(a.skip[i].weight, b.skip[i].weight) || !same(a.skip[i].bias, b.skip[i].bias)) return false;
  return same(a.input_mean, b.input_mean) && same(a.input_std, b.input_std) && same(a.head_weight, b.head_weight) &&
         same(a.head_bias, b.head_bias) && same(a.logvar_weight, b.logvar_weight) && same(a.logvar_bias, b.logvar_bias);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::optional<TcnFile> parsed;
  try {
    parsed = parseTcnFile(fuzz::bytesOf(data, size), "fuzz.tcn");
  } catch (const InputError&) {
    return 0;
  }
  const TcnFile& file = *parsed;
  for (TcnEncoding encoding : {TcnEncoding::kText, TcnEncoding::kFloat32}) {
    const std::string again = formatTcnFile(file.tcn, file.info, "round trip", encoding);
    try {
      const TcnFile back = parseTcnFile(again, "again.tcn");
      if (!sameWeights(back.tcn.weights(), file.tcn.weights())) {
        std::fprintf(stderr, "weights differ after a round trip\n");
        std::abort();
      }
    } catch (const InputError& e) {
      std::fprintf(stderr, "the writer's own output is rejected: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
