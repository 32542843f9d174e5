#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "hdvio/core/error.h"
#include "hdvio/io/csv.h"
#include "test_data.h"

namespace hdvio::io {
namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
  static const test::TempDir dir("csv");
  const std::string path = dir / name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(Csv, ParsesCrlfAndSpacesAndNumbers) {
  CsvReader csv(writeTemp("a.csv", "#timestamp [ns], x\r\n\r\n100, 1.5\r\n200,-2e-3 \r\n"));
  const auto header = csv.readHeader(true);
  ASSERT_EQ(header.size(), 2u);
  EXPECT_EQ(header[0], "timestamp [ns]");
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.line(), 3);
  EXPECT_EQ(csv.timestampNs(0), 100);
  EXPECT_EQ(csv.number(1), 1.5);
  ASSERT_TRUE(csv.next());
  EXPECT_EQ(csv.number(1), -2e-3);
  EXPECT_FALSE(csv.next());
}

TEST(Csv, ErrorsNameFileLineAndColumn) {
  const std::string path = writeTemp("b.csv", "#t,x\n1,abc\n");
  CsvReader csv(path);
  csv.readHeader(true);
  ASSERT_TRUE(csv.next());
  try {
    csv.number(1);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(e.problem().find("column 2 (x)"), std::string::npos) << e.what();
    EXPECT_NE(e.problem().find("not a number"), std::string::npos) << e.what();
  }
  for (const char* bad : {"nan", "inf", "-Inf", "1.5.2", "", "1 2"}) {
    CsvReader c(writeTemp("c.csv", std::string("#t,x\n1,") + bad + "\n"));
    c.readHeader(true);
    ASSERT_TRUE(c.next());
    EXPECT_THROW(c.number(1), InputError) << bad;
  }
  CsvReader c(writeTemp("d.csv", "#t,x\n1.5,2\n"));
  c.readHeader(true);
  ASSERT_TRUE(c.next());
  EXPECT_THROW(c.timestampNs(0), InputError);
  EXPECT_THROW(c.expectColumns(3), InputError);
}

TEST(Csv, HeaderRequiresHashForAsl) {
  CsvReader csv(writeTemp("e.csv", "t,x\n1,2\n"));
  EXPECT_THROW(csv.readHeader(true), InputError);
}

TEST(Csv, SecondsToNanosecondsIsExact) {
  Timestamp ns = 0;
  ASSERT_TRUE(parseSecondsToNs("1525745925.001598119736", &ns));
  EXPECT_EQ(ns, 1525745925001598120LL);
  ASSERT_TRUE(parseSecondsToNs("9.3325", &ns));
  EXPECT_EQ(ns, 9332500000LL);
  ASSERT_TRUE(parseSecondsToNs("-0.5", &ns));
  EXPECT_EQ(ns, -500000000LL);
  ASSERT_TRUE(parseSecondsToNs("12", &ns));
  EXPECT_EQ(ns, 12000000000LL);
  EXPECT_FALSE(parseSecondsToNs("1e3", &ns));
  EXPECT_FALSE(parseSecondsToNs("abc", &ns));
  EXPECT_FALSE(parseSecondsToNs(".", &ns));
}

// Ten whole-second digits passed the digit limit, and whole * 1e9 overflowed int64 (undefined
// behaviour) instead of falling back to the range check (docs/fuzzing.md).
TEST(Csv, SecondsBeyondInt64NanosecondsAreOutOfRange) {
  Timestamp ns = 0;
  EXPECT_FALSE(parseSecondsToNs("9999999999.5", &ns));
  EXPECT_FALSE(parseSecondsToNs("-9223372036", &ns));
  ASSERT_TRUE(parseSecondsToNs("9223372035.999999999", &ns));
  EXPECT_EQ(ns, 9223372035999999999LL);
  CsvReader csv(writeTemp("far.txt", "# ts x\n9999999999.5 1\n"), ' ');
  csv.readHeader(true);
  ASSERT_TRUE(csv.next());
  try {
    csv.secondsAsNs(0);
    ADD_FAILURE() << "accepted 9999999999.5 s";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(e.problem().find("time out of range"), std::string::npos) << e.what();
  }
}

TEST(Csv, WhitespaceDelimitedText) {
  CsvReader csv(writeTemp("f.txt", "# ts x y\n1.25  2 3\n"), ' ');
  const auto header = csv.readHeader(true);
  ASSERT_EQ(header.size(), 3u);
  EXPECT_EQ(header[0], "ts");
  ASSERT_TRUE(csv.next());
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv.secondsAsNs(0), 1250000000LL);
  EXPECT_EQ(csv.number(2), 3.0);
}

TEST(Csv, FormatDoubleRoundTrips) {
  for (double v : {0.1, 1.0 / 3.0, -9.81, 1e-300, 6.02214076e23}) {
    EXPECT_EQ(std::strtod(formatDouble(v).c_str(), nullptr), v);
  }
}

}  // namespace
}  // namespace hdvio::io
