#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <regex>

#include <gtest/gtest.h>

#include "../common/address_space_limit.h"
#include "deterministic_tcn.h"
#include "hdvio/core/error.h"
#include "hdvio/learned/tcn_weight_file.h"

namespace hdvio::learned {
namespace {

TEST(TcnWeightFile, RoundTripIsExact) {
  const Tcn tcn = testing::deterministicTcn();
  const std::string path = ::testing::TempDir() + "/roundtrip.tcn";
  saveTcnWeights(tcn, path, "unit test\nsecond comment line");
  const Tcn back = loadTcnWeights(path);
  EXPECT_EQ(back.parameterCount(), tcn.parameterCount());
  const MatrixXf x = testing::deterministicInputs(15);
  EXPECT_EQ((back.forwardSequence(x) - tcn.forwardSequence(x)).cwiseAbs().maxCoeff(), 0.0f);
  for (std::size_t l = 0; l < tcn.weights().conv.size(); ++l) {
    EXPECT_TRUE(back.weights().conv[l].weight == tcn.weights().conv[l].weight);
  }
  std::remove(path.c_str());
}

// Parsing `text` must fail with an InputError naming `line` and containing `problem`.
void expectFailure(const std::string& text, long line, const std::string& problem) {
  try {
    parseTcnWeights(text, "bad.tcn");
    ADD_FAILURE() << "accepted a malformed file, expected: " << problem;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "bad.tcn");
    if (line >= 0) {
      EXPECT_EQ(e.line(), line) << e.what();
    }
    EXPECT_NE(std::string(e.what()).find(problem), std::string::npos) << e.what();
  }
}

class MalformedWeights : public ::testing::Test {
 protected:
  void SetUp() override { good_ = formatTcnWeights(testing::deterministicTcn()); }
  // The file with line `n` (1-based) replaced.
  std::string withLine(long n, const std::string& replacement) const {
    std::istringstream in(good_);
    std::ostringstream out;
    long i = 0;
    for (std::string line; std::getline(in, line);) out << (++i == n ? replacement : line) << '\n';
    return out.str();
  }
  long lineOf(const std::string& prefix) const {
    std::istringstream in(good_);
    long i = 0;
    for (std::string line; std::getline(in, line);) {
      ++i;
      if (line.rfind(prefix, 0) == 0) return i;
    }
    return -1;
  }
  std::string good_;
};

TEST_F(MalformedWeights, GoodFileParses) { EXPECT_NO_THROW(parseTcnWeights(good_, "good.tcn")); }

TEST_F(MalformedWeights, MissingFile) {
  EXPECT_THROW(loadTcnWeights("/nonexistent/dir/weights.tcn"), InputError);
}

TEST_F(MalformedWeights, EmptyOrForeignFile) {
  expectFailure("", 0, "unexpected end of file");
  expectFailure("PK\x03\x04 binary junk\n", 1, "not an hdvio TCN weight file");
  expectFailure("hdvio_tcn 9\n", 1, "unsupported format version");
}

TEST_F(MalformedWeights, TruncatedFile) {
  const std::string cut = good_.substr(0, good_.size() / 2);
  expectFailure(cut.substr(0, cut.rfind('\n') + 1), -1, "unexpected end of file");
}

TEST_F(MalformedWeights, NonFiniteOrGarbageNumber) {
  const long row = lineOf("matrix conv2.weight") + 5;
  std::string line = withLine(row, "nan");
  expectFailure(line, row, "numbers");  // wrong count first
  std::istringstream in(good_);
  std::string original;
  for (long i = 0; i < row; ++i) std::getline(in, original);
  expectFailure(withLine(row, std::regex_replace(original, std::regex("^\\S+"), "nan")), row, "not a finite float");
  expectFailure(withLine(row, std::regex_replace(original, std::regex("^\\S+"), "1.5x")), row, "is not a number");
  expectFailure(withLine(row, std::regex_replace(original, std::regex("^\\S+"), "1e999")), row, "not a finite float");
}

TEST_F(MalformedWeights, WrongShapeOrOrder) {
  const long conv1 = lineOf("matrix conv1.weight");
  expectFailure(withLine(conv1, "matrix conv1.weight 64 127"), conv1, "shape of conv1.weight");
  expectFailure(withLine(conv1, "matrix conv9.weight 64 128"), conv1, "expected \"matrix conv1.weight");
  const long layer = lineOf("layer 64 2");
  expectFailure(withLine(layer, "layer 64 9"), lineOf("layer 128 1") + 2, "receptive field");
  expectFailure(withLine(lineOf("input_channels"), "input_channels six"), 2, "not an integer");
}

TEST_F(MalformedWeights, NonPositiveInputStd) {
  const long row = lineOf("vector input_std") + 1;
  expectFailure(withLine(row, "1 1 0 1 1 1"), row, "input_std must be positive");
}

TEST_F(MalformedWeights, ContentAfterEnd) {
  expectFailure(good_ + "matrix extra 1 1\n", -1, "after \"end\"");
}

// Found by fuzz_tcn_weights (docs/fuzzing.md): a float32 file may hold any finite float, but
// the text reader refused magnitudes above 3.0e38, so such a network saved as text was rejected.
TEST(TcnWeightFile, LargestFloatsRoundTripThroughText) {
  Tcn tcn = testing::deterministicTcn();
  TcnWeights w = tcn.weights();
  w.head_weight(0, 0) = -3.38953119e38f;
  w.head_weight(1, 0) = std::numeric_limits<float>::max();
  w.head_weight(2, 0) = -std::numeric_limits<float>::max();
  const Tcn big(tcn.architecture(), w);
  for (TcnEncoding encoding : {TcnEncoding::kText, TcnEncoding::kFloat32}) {
    const TcnFile back = parseTcnFile(formatTcnFile(big, TcnFileInfo{}, "", encoding), "big.tcn");
    EXPECT_TRUE(back.tcn.weights().head_weight == w.head_weight);
  }
  expectFailure(formatTcnWeights(big).replace(formatTcnWeights(big).find("-3.38953119e+38"), 15, "3.4028236e+38"),
                -1, "not a finite float");
}

// Seen while writing fuzz_tcn_weights (docs/fuzzing.md): "data <count>" allocated 4 * count
// bytes (up to 1 GiB) before looking whether the file holds them. In a child limited to 256 MiB
// more address space than it has, the short file must still be a plain InputError.
int parseWithLittleAddressSpace(const std::string& text) {
  hdvio::test::limitAddressSpaceGrowth(std::size_t{256} << 20);
  try {
    parseTcnFile(text, "huge.tcn");
  } catch (const InputError& e) {
    return std::string(e.what()).find("inside the float32 data") != std::string::npos ? 0 : 3;
  } catch (const std::bad_alloc&) {
    return 4;
  }
  return 5;
}

TEST(TcnWeightFile, Float32CountBeyondTheFileIsRejectedBeforeAllocating) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves address space beyond any RLIMIT_AS";
#else
  std::string text = formatTcnFile(testing::deterministicTcn(), TcnFileInfo{}, "", TcnEncoding::kFloat32);
  text = text.substr(0, text.find("\ndata ") + 1) + "data 268435455\n" + std::string(64, '\0');
  EXPECT_EXIT(std::exit(parseWithLittleAddressSpace(text)), ::testing::ExitedWithCode(0), "");
#endif
}

}  // namespace
}  // namespace hdvio::learned
