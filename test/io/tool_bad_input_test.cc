// Malformed copies of each input kind (ASL CSV / YAML / images, Blackbird and DIDO HDF5,
// NeuroBEM CSV, experiment YAML) through the tools users run: hdvio_info --check and hdvio_run
// must exit 2 with one `error: <file>:<line>: <problem>` line naming the bad file, and hdvio_run
// must leave no result folder. The readers themselves are covered by malformed_input_test.cc.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "../common/run_command.h"
#include "euroc_copy.h"
#include "test_data.h"

namespace hdvio::io {
namespace {
namespace fs = std::filesystem;

const std::string kVio = std::string(HDVIO_SOURCE_DIR) + "/config/experiments/vio.yaml";

using test::editLine;
using test::readLines;
using test::writeLines;

void truncateCopy(const std::string& from, const std::string& to, double fraction) {
  std::ifstream in(from, std::ios::binary);
  std::vector<char> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  b.resize(static_cast<std::size_t>(b.size() * fraction));
  std::ofstream(to, std::ios::binary | std::ios::trunc).write(b.data(), static_cast<long>(b.size()));
}

// The last line a tool printed (hdvio_run logs progress before it meets a bad image).
std::string lastLine(const std::string& output) {
  std::string s = output;
  while (!s.empty() && s.back() == '\n') s.pop_back();
  const std::size_t nl = s.rfind('\n');
  return nl == std::string::npos ? s : s.substr(nl + 1);
}

class ToolBadInput : public ::testing::Test {
 protected:
  // hdvio_info --check: exit 2, exactly one output line, starting with "error: <file>:<line>".
  void expectInfoError(const std::string& dataset, const std::string& located) {
    const auto o = hdvio::test::runCommand(std::string(HDVIO_INFO_BIN) + " --check " + dataset);
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_EQ(o.output.find("error: " + located), 0u) << o.output;
    EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << o.output;
  }
  // hdvio_run: exit 2, the last line is the error, and neither <out> nor <out>.partial exists.
  void expectRunError(const std::string& config, const std::string& dataset, const std::string& located) {
    const std::string out = dir_ / ("out" + std::to_string(runs_++));
    const auto o = hdvio::test::runCommand(std::string(HDVIO_RUN_BIN) + " --config " + config + " --dataset " +
                                    dataset + " --out " + out + " --noplots");
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_EQ(lastLine(o.output).find("error: " + located), 0u) << o.output;
    EXPECT_EQ(o.output.find("OpenCV"), std::string::npos) << o.output;
    EXPECT_FALSE(fs::exists(out)) << out;
    EXPECT_FALSE(fs::exists(out + ".partial")) << out;
  }
  void expectBothError(const std::string& dataset, const std::string& located) {
    expectInfoError(dataset, located);
    expectRunError(kVio, dataset, located);
  }
  test::TempDir dir_{"tool_bad_input"};
  int runs_ = 0;
};

// A private copy of the EuRoC excerpt: text files copied, images linked one by one.
class EurocToolCopy : public ToolBadInput {
 protected:
  void SetUp() override {
    HDVIO_REQUIRE_DATA(test::kEuroc);
    test::copyEurocExcerpt(dir_.path() / "seq", /*images_one_by_one=*/true);
    images_config_ = dir_ / "images.yaml";
    std::ofstream(images_config_) << "method: vio\nrun: {init_from_groundtruth: true}\nfrontend:\n"
                                     "  source: images\n";
  }
  std::string root() const { return dir_ / "seq"; }
  std::string mav0(const std::string& rel) const { return dir_ / ("seq/mav0/" + rel); }
  // The image listed on data.csv line `line`, replaced by a real file the test may damage.
  std::string ownImage(int line) {
    const std::string name = readLines(mav0("cam0/data.csv")).at(line - 1);
    const std::string path = mav0("cam0/data/" + name.substr(name.find(',') + 1));
    const fs::path target = fs::read_symlink(path);
    fs::remove(path);
    fs::copy_file(target, path);
    return path;
  }
  // hdvio_run on images meets the bad image at its frame: exit 2 at data.csv:<line>.
  void expectImageError(int line, const std::string& image, const std::string& problem) {
    const std::string located = mav0("cam0/data.csv") + ":" + std::to_string(line) + ": image " + image + ": ";
    expectInfoError(root(), located + problem);
    expectRunError(images_config_, root(), located + problem);
  }
  std::string images_config_;
};

TEST_F(EurocToolCopy, IntactCopyPassesTheCheck) {
  const auto o = hdvio::test::runCommand(std::string(HDVIO_INFO_BIN) + " --check " + root());
  EXPECT_EQ(o.exit_code, 0) << o.output;
  EXPECT_NE(o.output.find("check:    95 images decoded, all 752x480 8-bit as " + mav0("cam0/sensor.yaml")),
            std::string::npos)
      << o.output;
}

TEST_F(EurocToolCopy, CsvAndSensorYamlErrors) {
  editLine(mav0("imu0/data.csv"), 40, "garbage");
  expectBothError(root(), mav0("imu0/data.csv") + ":40: expected 7 columns, found 1");
  fs::copy_file(test::dataPath(test::kEuroc) + "/mav0/imu0/data.csv", mav0("imu0/data.csv"),
                fs::copy_options::overwrite_existing);
  editLine(mav0("cam0/data.csv"), 3, "nan,1403715273312143104.png");
  expectBothError(root(), mav0("cam0/data.csv") + ":3: ");
  fs::copy_file(test::dataPath(test::kEuroc) + "/mav0/cam0/data.csv", mav0("cam0/data.csv"),
                fs::copy_options::overwrite_existing);
  auto yaml = readLines(mav0("cam0/sensor.yaml"));
  for (auto& l : yaml)
    if (l.rfind("resolution:", 0) == 0) l = "resolutio: [752, 480]";
  writeLines(mav0("cam0/sensor.yaml"), yaml);
  expectBothError(root(), mav0("cam0/sensor.yaml"));
}

TEST_F(EurocToolCopy, ImageOfAnotherSize) {
  const std::string image = ownImage(6);
  cv::imwrite(image, cv::Mat(240, 376, CV_8UC1, cv::Scalar(90)));
  expectImageError(6, image, "image is 376x240 but " + mav0("cam0/sensor.yaml") + " says 752x480");
}

TEST_F(EurocToolCopy, TruncatedPng) {
  const std::string image = ownImage(6);
  truncateCopy(image, image + ".cut", 0.5);
  fs::rename(image + ".cut", image);
  expectImageError(6, image, "truncated PNG");
}

TEST_F(EurocToolCopy, EmptyImageFile) {
  const std::string image = ownImage(6);
  std::ofstream(image, std::ios::trunc).close();
  expectImageError(6, image, "image file is empty (0 bytes)");
}

TEST_F(ToolBadInput, ExperimentYamlWrongKeyAndWrongType) {
  HDVIO_REQUIRE_DATA(test::kEuroc);
  const std::string seq = test::dataPath(test::kEuroc);
  const std::string key = dir_ / "key.yaml";
  std::ofstream(key) << "method: vio\nbackend:\n  num_keyframe: 10\n";
  expectRunError(key, seq, key + ":3: ");
  const std::string type = dir_ / "type.yaml";
  std::ofstream(type) << "method: vio\nbackend:\n  num_keyframes: ten\n";
  expectRunError(type, seq, type + ":3: ");
}

TEST_F(ToolBadInput, TruncatedBlackbirdAndDidoHdf5) {
  HDVIO_REQUIRE_DATA(test::kBlackbirdVal);
  HDVIO_REQUIRE_DATA(test::kDido5Col);
  fs::create_directories(dir_ / "bb");
  fs::copy_file(test::dataPath(test::kBlackbirdVal) + "/stamped_groundtruth_imu.txt",
                dir_ / "bb/stamped_groundtruth_imu.txt");
  truncateCopy(test::dataPath(test::kBlackbirdVal) + "/data.hdf5", dir_ / "bb/data.hdf5", 0.5);
  expectBothError(dir_ / "bb", dir_ / "bb/data.hdf5");
  fs::create_directories(dir_ / "dido");
  truncateCopy(test::dataPath(test::kDido5Col) + "/data.hdf5", dir_ / "dido/data.hdf5", 0.5);
  expectBothError(dir_ / "dido", dir_ / "dido/data.hdf5");
}

TEST_F(ToolBadInput, NeuroBemShortRow) {
  HDVIO_REQUIRE_DATA(test::kNeuroBem);
  auto lines = readLines(test::dataPath(test::kNeuroBem));
  lines.resize(400);
  lines[150] = lines[150].substr(0, lines[150].rfind(','));
  const std::string f = dir_ / "seg.csv";
  writeLines(f, lines);
  expectBothError(f, f + ":151: expected 41 columns, found 40");
}

}  // namespace
}  // namespace hdvio::io
