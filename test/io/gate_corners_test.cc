// Gate map and corner detections: round trip through the writer, and every kind of bad input
// is an InputError naming the file and the line.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <fstream>

#include "hdvio/core/error.h"
#include "hdvio/io/gate_corners.h"
#include "test_data.h"

namespace hdvio::io {
namespace {

namespace fs = std::filesystem;

void writeText(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path) << text;
}

const char* kMapHeader = "#gate_id,corner_id,x [m],y [m],z [m]\n";
const char* kDetHeader = "#timestamp [ns],gate_id,corner_id,u [px],v [px]\n";

std::string validMap() { return std::string(kMapHeader) + "0,0,1,2,3\n0,1,1,-2,3\n3,2,4,5,6\n"; }

// Expects an InputError whose message names `file` and `line` and contains `what`.
void expectError(const std::function<void()>& f, const std::string& file, long line, const std::string& what) {
  try {
    f();
    FAIL() << "no error for " << what;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(e.problem().find(what), std::string::npos) << e.what();
  }
}

TEST(GateCorners, RoundTrip) {
  test::TempDir dir("gates_rt");
  GateData data;
  data.corners[{0, 0}] = Vec3(1.0, 2.0, 3.0);
  data.corners[{0, 3}] = Vec3(-1.0 / 3.0, 2.5e-7, 1e3);
  data.corners[{7, 1}] = Vec3(0.1, 0.2, 0.3);
  data.detections.push_back({1000, 0, 0, 10.25, 20.5});
  data.detections.push_back({1000, 7, 1, 1.0 / 7.0, 479.0});
  data.detections.push_back({2000, 0, 3, 0.0, 0.0});
  writeGateData(data, (dir.path() / "mav0").string());
  ASSERT_TRUE(hasGateData(dir.path().string()));
  const GateData back = readGateData(dir.path().string());  // finds mav0/ itself
  EXPECT_EQ(back.corners, data.corners);
  ASSERT_EQ(back.detections.size(), data.detections.size());
  for (std::size_t i = 0; i < data.detections.size(); ++i) {
    EXPECT_EQ(back.detections[i].t, data.detections[i].t);
    EXPECT_EQ(back.detections[i].gate_id, data.detections[i].gate_id);
    EXPECT_EQ(back.detections[i].corner_id, data.detections[i].corner_id);
    EXPECT_EQ(back.detections[i].u, data.detections[i].u);  // exact: full-precision text
    EXPECT_EQ(back.detections[i].v, data.detections[i].v);
  }
  // No temporary files left behind.
  for (const auto& e : fs::recursive_directory_iterator(dir.path()))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
}

TEST(GateCorners, MissingFilesNameTheFile) {
  test::TempDir dir("gates_missing");
  EXPECT_FALSE(hasGateData(dir.path().string()));
  expectError([&] { readGateData(dir.path().string()); }, (dir.path() / "gates0/gates.csv").string(), 0,
              "missing");
  writeText(dir / "gates0/gates.csv", validMap());
  expectError([&] { readGateData(dir.path().string()); }, (dir.path() / "gate_corners0/data.csv").string(), 0,
              "missing");
}

TEST(GateCorners, MalformedMap) {
  test::TempDir dir("gates_badmap");
  const std::string p = dir / "gates.csv";
  const struct {
    std::string body;
    long line;
    std::string what;
  } cases[] = {
      {"0,0,1,2\n", 2, "columns"},
      {"0,0,1,2,nan\n", 2, ""},
      {"0,0,1,2,3\n0,4,1,2,3\n", 3, "corner_id"},
      {"0,0,1,2,3\n0,0,1,2,3\n", 3, "duplicate"},
      {"-1,0,1,2,3\n", 2, "gate_id"},
      {"0,x,1,2,3\n", 2, ""},
  };
  for (const auto& c : cases) {
    writeText(p, kMapHeader + c.body);
    expectError([&] { readGateMap(p); }, p, c.line, c.what);
  }
  writeText(p, "0,0,1,2,3\n");  // no '#' header
  EXPECT_THROW(readGateMap(p), InputError);
  writeText(p, kMapHeader);
  EXPECT_THROW(readGateMap(p), InputError);  // no corners
}

TEST(GateCorners, MalformedDetections) {
  test::TempDir dir("gates_baddet");
  const std::string m = dir / "gates.csv", p = dir / "data.csv";
  writeText(m, validMap());
  const GateCornerMap map = readGateMap(m);
  EXPECT_EQ(map.size(), 3u);
  const struct {
    std::string body;
    long line;
    std::string what;
  } cases[] = {
      {"100,0,0,1.0\n", 2, "columns"},
      {"100,0,0,1.0,inf\n", 2, ""},
      {"100,0,0,nan,2\n", 2, ""},
      {"200,0,0,1,2\n100,0,1,1,2\n", 3, "non-monotonic"},
      {"100,1,0,1,2\n", 2, "not in the gate map"},
      {"100,0,2,1,2\n", 2, "not in the gate map"},
      {"100,0,0,1,2\n100,0,0,1,2\n", 3, "duplicate"},
      {"1.5,0,0,1,2\n", 2, ""},
  };
  for (const auto& c : cases) {
    writeText(p, kDetHeader + c.body);
    expectError([&] { readGateCorners(p, map); }, p, c.line, c.what);
  }
  writeText(p, std::string(kDetHeader) + "100,0,0,1,2\n100,0,1,3,4\n300,3,2,5,6\n");
  EXPECT_EQ(readGateCorners(p, map).size(), 3u);
}

}  // namespace
}  // namespace hdvio::io
