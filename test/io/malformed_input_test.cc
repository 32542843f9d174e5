// Corrupted copies of real files: every problem must surface as one InputError naming the
// file, the line and the problem, and the apps must exit with code 2.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "hdvio/core/error.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/datasets.h"
#include "hdvio/io/sequence_reader.h"
#include "euroc_copy.h"
#include "hdf5_dataset_writer.h"
#include "test_data.h"

namespace hdvio::io {
namespace {
namespace fs = std::filesystem;

using test::editLine;
using test::readLines;
using test::writeLines;

std::string field(const std::string& line, int i) {
  std::stringstream ss(line);
  std::string f;
  for (int k = 0; k <= i; ++k) std::getline(ss, f, ',');
  return f;
}

// A private copy of the EuRoC excerpt: CSV and YAML files copied, images linked.
class EurocCopy : public ::testing::Test {
 protected:
  void SetUp() override {
    HDVIO_REQUIRE_DATA(test::kEuroc);
    test::copyEurocExcerpt(dir_.path() / "seq");
  }
  // Replaces the linked image folder by a folder of per-image links, which a test may edit.
  void linkImagesOneByOne() {
    const fs::path src = fs::read_symlink(mav0("cam0/data"));
    fs::remove(mav0("cam0/data"));
    fs::create_directories(mav0("cam0/data"));
    for (const auto& e : fs::directory_iterator(src))
      fs::create_symlink(e.path(), fs::path(mav0("cam0/data")) / e.path().filename());
  }
  std::string root() const { return dir_ / "seq"; }
  std::string mav0(const std::string& rel) const { return dir_ / ("seq/mav0/" + rel); }

  // Reading must fail with exactly this file and line, and a problem containing `what`.
  void expectError(const std::string& file, long line, const std::string& what, const ReadOptions& o = {}) {
    try {
      readSequence(root(), o);
      ADD_FAILURE() << "no error; expected " << what;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), file) << e.what();
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(e.problem().find(what), std::string::npos) << e.what();
    }
  }

  test::TempDir dir_{"malformed"};
};

TEST_F(EurocCopy, IntactCopyReads) {
  const Sequence seq = readSequence(root());
  EXPECT_EQ(seq.imu.size(), 1141u);
  EXPECT_EQ(seq.images.size(), 95u);
}

TEST_F(EurocCopy, DroppedColumn) {
  const std::string f = mav0("imu0/data.csv");
  auto lines = readLines(f);
  lines[9] = lines[9].substr(0, lines[9].rfind(','));
  writeLines(f, lines);
  expectError(f, 10, "expected 7 columns, found 6");
}

TEST_F(EurocCopy, ExtraColumn) {
  const std::string f = mav0("imu0/data.csv");
  auto lines = readLines(f);
  lines[11] += ",0.5";
  writeLines(f, lines);
  expectError(f, 12, "expected 7 columns, found 8");
}

TEST_F(EurocCopy, NonNumericField) {
  const std::string f = mav0("imu0/data.csv");
  editLine(f, 30, field(readLines(f)[29], 0) + ",0.1,abc,0.3,9.8,0.1,0.2");
  expectError(f, 30, "column 3 (w_RS_S_y [rad s^-1]): not a number: 'abc'");
}

TEST_F(EurocCopy, NanField) {
  const std::string f = mav0("state_groundtruth_estimate0/data.csv");
  auto lines = readLines(f);
  lines[4].replace(lines[4].find(',') + 1, lines[4].find(',', lines[4].find(',') + 1) - lines[4].find(',') - 1, "nan");
  writeLines(f, lines);
  expectError(f, 5, "non-finite value 'nan'");
}

TEST_F(EurocCopy, SwappedTimestamps) {
  const std::string f = mav0("imu0/data.csv");
  auto lines = readLines(f);
  std::swap(lines[20], lines[21]);
  writeLines(f, lines);
  expectError(f, 22, "non-monotonic timestamp");
}

TEST_F(EurocCopy, ExactDuplicateRowIsAWarning) {
  const std::string f = mav0("imu0/data.csv");
  auto lines = readLines(f);
  lines.insert(lines.begin() + 50, lines[50]);
  writeLines(f, lines);
  const Sequence seq = readSequence(root());
  EXPECT_EQ(seq.imu.size(), 1141u);
  ASSERT_EQ(seq.warnings.size(), 1u);
  EXPECT_NE(seq.warnings[0].find("dropped 1 exactly duplicated row"), std::string::npos) << seq.warnings[0];
}

TEST_F(EurocCopy, DuplicateTimestampWithOtherValues) {
  const std::string f = mav0("imu0/data.csv");
  auto lines = readLines(f);
  lines.insert(lines.begin() + 50, field(lines[50], 0) + ",0,0,0,0,0,9.81");
  writeLines(f, lines);
  expectError(f, 52, "duplicate timestamp");
}

TEST_F(EurocCopy, ImuGapAboveThreshold) {
  const std::string f = mav0("imu0/data.csv");
  auto lines = readLines(f);
  lines.erase(lines.begin() + 100, lines.begin() + 120);  // 0.1 s missing
  writeLines(f, lines);
  expectError(f, 101, "IMU gap of 0.1050 s");
  ReadOptions lenient;
  lenient.max_imu_gap_s = 0.2;
  EXPECT_EQ(readSequence(root(), lenient).imu.size(), 1121u);
}

TEST_F(EurocCopy, CrlfLineEndingsReadTheSame) {
  const Sequence before = readSequence(root());
  writeLines(mav0("imu0/data.csv"), readLines(mav0("imu0/data.csv")), "\r\n");
  const Sequence after = readSequence(root());
  ASSERT_EQ(after.imu.size(), before.imu.size());
  EXPECT_EQ(after.imu.back().accel, before.imu.back().accel);
}

TEST_F(EurocCopy, MissingImage) {
  linkImagesOneByOne();
  const auto lines = readLines(mav0("cam0/data.csv"));
  fs::remove(fs::path(mav0("cam0/data")) / field(lines[7], 1));
  expectError(mav0("cam0/data.csv"), 8, "image file does not exist");
}

TEST_F(EurocCopy, MissingSensorYamlKey) {
  const std::string f = mav0("cam0/sensor.yaml");
  auto lines = readLines(f);
  lines.erase(std::remove_if(lines.begin(), lines.end(),
                             [](const std::string& l) { return l.rfind("intrinsics:", 0) == 0; }),
              lines.end());
  writeLines(f, lines);
  expectError(f, 0, "missing key 'intrinsics'");
}

TEST_F(EurocCopy, RepeatedSensorYamlKey) {
  const std::string f = mav0("cam0/sensor.yaml");
  auto lines = readLines(f);
  const auto it = std::find_if(lines.begin(), lines.end(),
                               [](const std::string& l) { return l.rfind("intrinsics:", 0) == 0; });
  ASSERT_NE(it, lines.end());
  const long first_line = static_cast<long>(it - lines.begin()) + 1;
  lines.push_back("intrinsics: [400.0, 400.0, 360.0, 240.0]");
  writeLines(f, lines);
  expectError(f, static_cast<long>(lines.size()),
              "key 'intrinsics' repeats the one on line " + std::to_string(first_line));
}

TEST_F(EurocCopy, InconsistentCameraCalibration) {
  const std::string f = mav0("cam0/sensor.yaml");
  const auto original = readLines(f);
  auto replace = [&](const std::string& prefix, const std::string& text) {
    auto lines = original;
    for (auto& l : lines) {
      if (l.rfind(prefix, 0) == 0) l = text;
    }
    writeLines(f, lines);
  };
  replace("intrinsics:", "intrinsics: [458.654, -457.296, 367.215, 248.375]");
  expectError(f, 19, "fu, fv, cu, cv must be positive");
  replace("distortion_coefficients:", "distortion_coefficients: [-0.28, 0.07, 0.0002]");
  expectError(f, 21, "expected 4 values, found 3");
  replace("distortion_model:", "distortion_model: fisheye62");
  expectError(f, 20, "unknown model 'fisheye62'");
  replace("  data: [0.0148655429818", "  data: [0.5148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,");
  expectError(f, 10, "rotation part is not orthonormal");
}

// Bugs met while fuzzing the readers (docs/fuzzing.md). Stamps of opposite sign overflowed
// t - previous in the gap check (undefined), which wrapped to a negative gap and let it pass.
TEST_F(EurocCopy, ImuStampsFarApartAreAGap) {
  const std::string f = mav0("imu0/data.csv");
  auto lines = readLines(f);
  lines[1] = "-9000000000000000000" + lines[1].substr(lines[1].find(','));
  lines[2] = "9000000000000000000" + lines[2].substr(lines[2].find(','));
  writeLines(f, lines);
  expectError(f, 3, "IMU gap of inf s");
}

// A resolution beyond int was cast to int before the check (undefined behaviour; on
// x86 the check still failed, so only a UBSan build, scripts/test.sh --sanitize, tells).
TEST_F(EurocCopy, CameraResolutionBeyondInt) {
  const std::string f = mav0("cam0/sensor.yaml");
  auto lines = readLines(f);
  for (auto& l : lines) {
    if (l.rfind("resolution:", 0) == 0) l = "resolution: [1e300, 480]";
  }
  writeLines(f, lines);
  expectError(f, 17, "expected two positive integers");
}

TEST_F(EurocCopy, MissingImuFolder) {
  fs::remove_all(mav0("imu0"));
  try {
    readSequence(root());
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("imu0 is required"), std::string::npos) << e.what();
  }
}

// Runs a tool, returning its exit code and its stderr.
int run(const std::string& command, std::string* err) {
  const test::TempDir tmp("stderr");
  const std::string err_file = tmp / "err.txt";
  const int status = std::system((command + " > /dev/null 2> " + err_file).c_str());
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  *err = ss.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST_F(EurocCopy, InfoAppExitsWithCode2AndOneLine) {
  std::string err;
  EXPECT_EQ(run(std::string(HDVIO_INFO_BIN) + " " + root(), &err), 0) << err;
  editLine(mav0("imu0/data.csv"), 40, "garbage");
  EXPECT_EQ(run(std::string(HDVIO_INFO_BIN) + " " + root(), &err), 2);
  EXPECT_EQ(err, "error: " + mav0("imu0/data.csv") + ":40: expected 7 columns, found 1\n");
  EXPECT_EQ(run(std::string(HDVIO_INFO_BIN), &err), 2);  // usage
  EXPECT_EQ(run(std::string(HDVIO_INFO_BIN) + " " + (dir_ / "nope"), &err), 2);
  EXPECT_NE(err.find("no such file or directory"), std::string::npos) << err;
}

TEST(MalformedDatasets, NotAnHdf5File) {
  const test::TempDir dir("nothdf5");
  fs::create_directories(dir / "seq");
  std::ofstream(dir / "seq/data.hdf5") << "import numpy as np\n";
  try {
    readSequence(dir / "seq");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.problem(), "not an HDF5 file");
  }
  std::string err;
  EXPECT_EQ(run(std::string(HDVIO_INFO_BIN) + " " + (dir / "seq"), &err), 2);
}

using test::writeDataset;

// A small Blackbird-layout file built from the first real rows, then corrupted.
TEST(MalformedDatasets, BlackbirdHdf5Errors) {
  HDVIO_REQUIRE_DATA(test::kBlackbirdVal);
  const Sequence real = readBlackbird(test::dataPath(test::kBlackbirdVal));
  const std::size_t n = 50;
  std::vector<double> ts, gyro, accel, thrust;
  for (std::size_t i = 0; i < n; ++i) {
    ts.push_back(toSeconds(real.imu[i].t));
    for (int k = 0; k < 3; ++k) {
      gyro.push_back(real.imu[i].gyro[k]);
      accel.push_back(real.imu[i].accel[k]);
      thrust.push_back(real.thrust[i].thrust[k]);
    }
  }
  auto build = [&](const std::string& path, std::vector<double> t, std::vector<double> a) {
    const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    writeDataset(f, "ts", t, 1);
    writeDataset(f, "gyro_calib", gyro, 3);
    writeDataset(f, "accel_calib", a, 3);
    writeDataset(f, "thrust", thrust, 3);
    H5Fclose(f);
  };
  const test::TempDir dir("bbh5");
  fs::create_directories(dir / "train");
  const std::string h5 = dir / "train/data.hdf5";
  build(h5, ts, accel);
  EXPECT_EQ(readSequence(dir / "train").imu.size(), n);

  auto nan_accel = accel;
  nan_accel[3 * 7 + 2] = std::nan("");
  build(h5, ts, nan_accel);
  try {
    readSequence(dir / "train");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), h5 + "[accel_calib]");
    EXPECT_EQ(e.line(), 8);
    EXPECT_NE(e.problem().find("non-finite value in column 3"), std::string::npos) << e.what();
  }
  auto swapped = ts;
  std::swap(swapped[10], swapped[11]);
  build(h5, swapped, accel);
  try {
    readSequence(h5);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), h5 + "[ts]");
    EXPECT_EQ(e.line(), 12);
    EXPECT_NE(e.problem().find("non-monotonic"), std::string::npos) << e.what();
  }
}

// fuzz_hdf5_datasets / fuzz_hdf5_raw: a chunked dataset that was never written declares its
// shape in a few bytes; the reader allocated rows x cols doubles for it (std::length_error or
// bad_alloc escaping the reader, or an overflowed product). The shape is now bounded.
TEST(MalformedDatasets, HugeDeclaredShapeIsAnInputError) {
  const test::TempDir dir("h5shape");
  fs::create_directories(dir / "seq");
  const std::string h5 = dir / "seq/data.hdf5";
  for (const hsize_t rows : {hsize_t{1} << 40, hsize_t{1} << 62}) {
    const hid_t f = H5Fcreate(h5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t dims[1] = {rows}, chunk[1] = {64};
    const hid_t space = H5Screate_simple(1, dims, nullptr);
    const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, chunk);
    H5Dclose(H5Dcreate2(f, "ts", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT));
    H5Pclose(dcpl);
    H5Sclose(space);
    H5Fclose(f);
    ASSERT_LT(fs::file_size(h5), 10000u);
    for (bool dido : {false, true}) {
      try {
        dido ? readDido(dir / "seq") : readBlackbird(dir / "seq");
        ADD_FAILURE() << "accepted a dataset of " << rows << " rows";
      } catch (const InputError& e) {
        EXPECT_EQ(e.file(), h5 + "[ts]");
        EXPECT_NE(e.problem().find("larger than the readers accept"), std::string::npos) << e.what();
      }
    }
  }
}

// fuzz_hdf5_raw: a compact dataset whose layout message stores fewer bytes than its shape needs
// made libhdf5 1.10 copy out of bounds inside H5Dread (a segfault). The reader now compares the
// stored bytes with the shape first. The file is written by libhdf5 and the compact size field
// (the two bytes before the data in the layout message) patched.
TEST(MalformedDatasets, StorageSmallerThanShapeIsAnInputError) {
  const test::TempDir dir("h5storage");
  fs::create_directories(dir / "seq");
  const std::string h5 = dir / "seq/data.hdf5";
  const std::vector<double> ts{1.25, 2.5, 3.75};
  const hid_t f = H5Fcreate(h5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hsize_t dims[1] = {ts.size()};
  const hid_t space = H5Screate_simple(1, dims, nullptr);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_layout(dcpl, H5D_COMPACT);
  const hid_t d = H5Dcreate2(f, "ts", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, ts.data());
  H5Dclose(d);
  H5Pclose(dcpl);
  H5Sclose(space);
  H5Fclose(f);
  std::ifstream in(h5, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const std::string data(reinterpret_cast<const char*>(ts.data()), ts.size() * sizeof(double));
  const std::size_t at = bytes.find(data);
  ASSERT_NE(at, std::string::npos);
  ASSERT_GE(at, 4u);
  ASSERT_EQ(bytes.substr(at - 4, 4), std::string("\x03\x00\x18\x00", 4));  // v3, compact, 24 bytes
  for (const char stored : {'\x00', '\x08'}) {
    bytes[at - 2] = stored;
    std::ofstream(h5, std::ios::binary) << bytes;
    for (bool dido : {false, true}) {
      try {
        dido ? readDido(dir / "seq") : readBlackbird(dir / "seq");
        ADD_FAILURE() << "accepted " << int(stored) << " stored bytes for 3 values";
      } catch (const InputError& e) {
        EXPECT_EQ(e.file(), h5 + "[ts]");
        EXPECT_NE(e.problem().find("damaged dataset"), std::string::npos) << e.what();
      }
    }
  }
}

// Files on which libhdf5 1.10.8 itself crashed (test/io/data/README.md): one clear error naming
// the file, from the readers and from the tools (libhdf5 runs in a child process).
TEST(MalformedDatasets, FilesThatCrashLibhdf5AreInputErrors) {
  for (const char* name : {"libhdf5_crash_compact_dataset.hdf5", "libhdf5_crash_symbol_table.hdf5"}) {
    SCOPED_TRACE(name);
    const test::TempDir dir("h5crash");
    fs::create_directories(dir / "seq");
    const std::string h5 = dir / "seq/data.hdf5";
    fs::copy_file(std::string(HDVIO_TEST_IO_DATA) + "/" + name, h5);
    for (int reader = 0; reader < 3; ++reader) {
      try {
        reader == 0 ? readDido(dir / "seq") : reader == 1 ? readBlackbird(dir / "seq") : readSequence(dir / "seq");
        ADD_FAILURE() << "accepted";
      } catch (const InputError& e) {
        EXPECT_EQ(e.file().rfind(h5, 0), 0u) << e.what();  // the file, or one of its datasets
      }
    }
    std::string err;
    EXPECT_EQ(run(std::string(HDVIO_INFO_BIN) + " " + h5, &err), 2) << err;
    EXPECT_EQ(err.rfind("error: " + h5, 0), 0u) << err;
    // Only that line: nothing the crashing child printed (a sanitizer's report in those builds).
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  }
}

// A time of 1e300 s was converted to int64 ns (undefined behaviour).
TEST(MalformedDatasets, HdfTimeBeyondInt64Nanoseconds) {
  const test::TempDir dir("h5time");
  fs::create_directories(dir / "seq");
  const std::string h5 = dir / "seq/data.hdf5";
  const hid_t f = H5Fcreate(h5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  writeDataset(f, "ts", {1.0, 2.0, 1e300}, 1);
  for (const char* name : {"gyro_calib", "accel_calib", "thrust"}) writeDataset(f, name, std::vector<double>(9, 0.5), 3);
  H5Fclose(f);
  try {
    readBlackbird(dir / "seq");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), h5 + "[ts]");
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(e.problem().find("out of range"), std::string::npos) << e.what();
  }
}

TEST(MalformedDatasets, BlackbirdGroundTruthText) {
  HDVIO_REQUIRE_DATA(test::kBlackbirdVal);
  const test::TempDir dir("bbtxt");
  fs::create_directories(dir / "val");
  fs::copy_file(test::dataPath(test::kBlackbirdVal) + "/data.hdf5", dir / "val/data.hdf5");
  auto lines = readLines(test::dataPath(test::kBlackbirdVal) + "/stamped_groundtruth_imu.txt");
  lines[99] = lines[99].substr(0, lines[99].find(' ')) + " 1 2 3 0 0 0 1 nan 0 0";
  writeLines(dir / "val/stamped_groundtruth_imu.txt", lines);
  try {
    readSequence(dir / "val");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), dir / "val/stamped_groundtruth_imu.txt");
    EXPECT_EQ(e.line(), 100);
    EXPECT_NE(e.problem().find("non-finite"), std::string::npos) << e.what();
  }
}

TEST(MalformedDatasets, NeuroBemShortRowAndMissingColumn) {
  HDVIO_REQUIRE_DATA(test::kNeuroBem);
  const test::TempDir dir("nbcsv");
  auto lines = readLines(test::dataPath(test::kNeuroBem));
  lines.resize(200);
  const std::string f = dir / "seg.csv";
  auto short_row = lines;
  short_row[150] = short_row[150].substr(0, short_row[150].rfind(','));
  writeLines(f, short_row);
  try {
    readSequence(f);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 151);
    EXPECT_NE(e.problem().find("expected 41 columns, found 40"), std::string::npos) << e.what();
  }
  auto renamed = lines;
  renamed[0].replace(renamed[0].find(",acc_y,") + 1, 5, "acc_q");
  writeLines(f, renamed);
  try {
    readSequence(f);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.problem(), "missing column 'acc_y'");
  }
}

TEST(ConvertApp, WritesReadableAslAndRefusesToOverwrite) {
  HDVIO_REQUIRE_DATA(test::kDido5Col);
  const test::TempDir dir("convert");
  const std::string out = dir / "out";
  const std::string cmd = std::string(HDVIO_CONVERT_BIN) + " --input " + test::dataPath(test::kDido5Col) +
                          " --output " + out;
  std::string err;
  ASSERT_EQ(run(cmd, &err), 0) << err;
  const Sequence back = readAsl(out);
  const Sequence direct = readDido(test::dataPath(test::kDido5Col));
  EXPECT_EQ(back.imu.size(), direct.imu.size());
  EXPECT_EQ(back.rotor.back().speeds, direct.rotor.back().speeds);
  EXPECT_EQ(run(cmd, &err), 2);
  EXPECT_NE(err.find("not empty"), std::string::npos) << err;
  EXPECT_EQ(run(cmd + " --force", &err), 0) << err;
  std::ofstream(out + "/notes.txt") << "not part of a conversion\n";
  EXPECT_EQ(run(cmd + " --force", &err), 2);  // --force never deletes unrelated files
  EXPECT_TRUE(fs::exists(out + "/notes.txt"));
  EXPECT_EQ(run(std::string(HDVIO_CONVERT_BIN) + " --input " + test::dataPath("dido/data.hdf5") + " --output " +
                    (dir / "bad"),
                &err),
            2);
  EXPECT_FALSE(fs::exists(dir / "bad"));
  EXPECT_EQ(run(std::string(HDVIO_CONVERT_BIN) + " --output " + (dir / "bad"), &err), 2);  // usage
}

}  // namespace
}  // namespace hdvio::io
