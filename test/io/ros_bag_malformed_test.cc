// Broken bags and topic maps: every problem is one InputError naming the file and the problem,
// and the tools exit with code 2 without writing anything.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "../common/address_space_limit.h"
#include "../common/run_command.h"
#include "bag_flight.h"
#include "hdvio/core/error.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/image.h"
#include "hdvio/io/ros_bag.h"
#include "hdvio/io/sequence_reader.h"
#include "test_data.h"

namespace hdvio::io {
namespace {
namespace fs = std::filesystem;
using test::writeBytes;

class BrokenBag : public ::testing::Test {
 protected:
  void SetUp() override {
    const test::FlightOnDisk f = test::writeFlight(dir_.path());
    flight_ = f.flight;
    options_ = f.options;
    good_ = test::flightBag(flight_, "none");
  }
  ReadOptions options() const { return options_; }
  // Reading `bytes` as a bag must fail naming `file` (default: the bag) and containing `what`.
  void expectError(const std::string& bytes, const std::string& what, const ReadOptions& o,
                   std::string file = "") {
    const std::string bag = dir_ / "broken.bag";
    writeBytes(bag, bytes);
    if (file.empty()) file = bag;
    try {
      readSequence(bag, o);
      ADD_FAILURE() << "no error; expected " << what;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), file) << e.what();
      EXPECT_NE(e.problem().find(what), std::string::npos) << e.what();
    }
  }
  void expectError(const std::string& bytes, const std::string& what) { expectError(bytes, what, options()); }

  // An IMU-only bag with one extra connection on `topic` of `type` holding `message`.
  std::string imuBagWith(const std::string& topic, const std::string& type, const std::string& message) const {
    test::BagWriter w;
    const auto imu = w.connection("/imu0", "sensor_msgs/Imu");
    for (const auto& s : flight_.seq.imu) w.write(imu, s.t, test::imuMessage(s));
    const auto other = w.connection(topic, type);
    w.write(other, test::kT0, message);
    return w.finish();
  }

  test::TempDir dir_{"badbag"};
  test::Flight flight_;
  ReadOptions options_;
  std::string good_;
};

TEST_F(BrokenBag, IntactBagReads) {
  writeBytes(dir_ / "good.bag", good_);
  EXPECT_EQ(readSequence(dir_ / "good.bag", options()).imu.size(), 200u);
}

TEST_F(BrokenBag, TruncatedAnywhere) {
  // Every cut after the magic: inside the header, a chunk, an index record, or exactly at a
  // record boundary of the index section.
  for (std::size_t cut = 20; cut < good_.size(); cut += good_.size() / 97) {
    SCOPED_TRACE(cut);
    expectError(good_.substr(0, cut), "truncated");
  }
  expectError(good_.substr(0, good_.size() - 1), "truncated");
  // Exactly before the last chunk info record: every record is whole, the count is short.
  const std::size_t last_info = good_.rfind(std::string("op=") + '\x06');
  ASSERT_NE(last_info, std::string::npos);
  expectError(good_.substr(0, last_info - 8), "truncated or inconsistent bag");
  expectError(good_.substr(0, 8), "not a ROS bag");
}

TEST_F(BrokenBag, BadMagicAndVersion) {
  std::string bad = good_;
  bad[1] = 'X';
  expectError(bad, "not a ROS bag");
  bad = good_;
  bad.replace(9, 3, "1.2");
  expectError(bad, "unsupported bag version '1.2'");
  expectError("", "not a ROS bag");
}

TEST_F(BrokenBag, WrongTypeOnAMappedTopic) {
  expectError(imuBagWith("/rotors", "geometry_msgs/PoseStamped", test::poseStampedMessage(flight_.seq.groundtruth[0])),
              "topic /rotors (rotor_speeds) has type geometry_msgs/PoseStamped, expected mav_msgs/Actuators");
  // The right type name over the wrong bytes: the size check catches it.
  expectError(imuBagWith("/rotors", "mav_msgs/Actuators", test::vector3StampedMessage(flight_.seq.thrust[0])),
              "/rotors message 1: ");
}

TEST_F(BrokenBag, MissingTopics) {
  ReadOptions no_map = options();
  no_map.bag_topics.clear();
  // The map names /cam0/image_raw, /rotors, ..., which this bag lacks.
  expectError(imuBagWith("/other", "geometry_msgs/PoseStamped", test::poseStampedMessage(flight_.seq.groundtruth[0])),
              "missing topic /cam0/image_raw (camera); the bag holds: /imu0 (sensor_msgs/Imu), /other");
  // Without a map, absent default topics other than the IMU are skipped...
  writeBytes(dir_ / "imu_only.bag", imuBagWith("/other", "geometry_msgs/PoseStamped",
                                               test::poseStampedMessage(flight_.seq.groundtruth[0])));
  EXPECT_EQ(readSequence(dir_ / "imu_only.bag", no_map).images.size(), 0u);
  // ... but the IMU is required.
  test::BagWriter w;
  const auto gt = w.connection("/vicon/firefly_sbx/firefly_sbx", "geometry_msgs/PoseStamped");
  w.write(gt, test::kT0, test::poseStampedMessage(flight_.seq.groundtruth[0]));
  expectError(w.finish(), "missing topic /imu0 (imu)", no_map);
}

TEST_F(BrokenBag, UnsortedOrDuplicateHeaderStamps) {
  test::BagWriter w;
  const auto imu = w.connection("/imu0", "sensor_msgs/Imu");
  auto s = flight_.seq.imu;
  std::swap(s[10].t, s[11].t);  // stamps backwards while record times go forward
  for (std::size_t i = 0; i < s.size(); ++i) w.write(imu, test::kT0 + i, test::imuMessage(s[i]));
  ReadOptions no_map;
  expectError(w.finish(), "/imu0 message 12 (in record-time order): non-monotonic timestamp", no_map);

  test::BagWriter d;
  const auto imu2 = d.connection("/imu0", "sensor_msgs/Imu");
  s = flight_.seq.imu;
  s[11].t = s[10].t;
  for (std::size_t i = 0; i < s.size(); ++i) d.write(imu2, test::kT0 + i, test::imuMessage(s[i]));
  expectError(d.finish(), "duplicate timestamp", no_map);
}

TEST_F(BrokenBag, CompressionProblems) {
  std::string bad = good_;
  const std::size_t at = bad.find("compression=none");
  ASSERT_NE(at, std::string::npos);
  bad.replace(at, 16, "compression=zstd");
  expectError(bad, "unsupported chunk compression 'zstd'");
  std::string bz2 = test::flightBag(flight_, "bz2");
  const std::size_t data = bz2.find("BZh");
  ASSERT_NE(data, std::string::npos);
  bz2[data + 20] ^= 0x55;
  expectError(bz2, "bz2 data cannot be decompressed");
  std::string lz4 = test::flightBag(flight_, "lz4");
  const std::size_t frame = lz4.find("\x04\x22\x4d\x18");
  ASSERT_NE(frame, std::string::npos);
  lz4[frame + 1] = 0x00;  // broken magic
  expectError(lz4, "lz4: ");
}

// Met while fuzzing (docs/fuzzing.md): a bz2 or lz4 chunk declaring 1 GiB made the reader
// allocate (and zero) 1 GiB before decompressing a few bytes. In a child limited to 256 MiB
// more address space than it has, both must still be plain InputErrors.
int readWithLittleAddressSpace(const std::string& bag, const ReadOptions& o, const std::string& what) {
  hdvio::test::limitAddressSpaceGrowth(std::size_t{256} << 20);
  try {
    readSequence(bag, o);
  } catch (const InputError& e) {
    return e.problem().find(what) != std::string::npos ? 0 : 3;
  } catch (const std::bad_alloc&) {
    return 4;
  }
  return 5;
}

TEST_F(BrokenBag, ChunkDeclaringAGibibyteIsRejectedBeforeAllocating) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves address space beyond any RLIMIT_AS";
#else
  for (const auto& [compression, what] : {std::pair<std::string, std::string>{"bz2", "its header says 1073741823"},
                                          {"lz4", "declares 1073741823 uncompressed bytes from"}}) {
    std::string bag = test::flightBag(flight_, compression);
    const std::size_t size = bag.find("size=", bag.find("compression=" + compression));
    ASSERT_NE(size, std::string::npos);
    const std::uint32_t huge = (1u << 30) - 1;
    std::memcpy(&bag[size + 5], &huge, 4);
    writeBytes(dir_ / "huge.bag", bag);
    EXPECT_EXIT(std::exit(readWithLittleAddressSpace(dir_ / "huge.bag", options(), what)),
                ::testing::ExitedWithCode(0), "")
        << compression;
  }
#endif
}

TEST_F(BrokenBag, UnindexedBag) {
  test::BagWriter w;
  w.unindexed = true;
  const auto imu = w.connection("/imu0", "sensor_msgs/Imu");
  w.write(imu, test::kT0, test::imuMessage(flight_.seq.imu[0]));
  expectError(w.finish(), "bag is not indexed", ReadOptions{});
}

TEST_F(BrokenBag, NonFiniteValues) {
  ImuSample s = flight_.seq.imu[3];
  s.accel.y() = std::numeric_limits<double>::quiet_NaN();
  test::BagWriter w;
  const auto imu = w.connection("/imu0", "sensor_msgs/Imu");
  w.write(imu, s.t, test::imuMessage(s));
  expectError(w.finish(), "/imu0 message 1: non-finite number", ReadOptions{});
}

TEST_F(BrokenBag, CalibrationProblems) {
  ReadOptions o = options();
  o.calibration.clear();
  expectError(good_, "bags carry no calibration", o, "--calibration");
  // Images of another size than cam0/sensor.yaml says.
  test::Flight small = flight_;
  for (auto& f : small.frames) f = f(cv::Rect(0, 0, 20, 10)).clone();
  expectError(test::flightBag(small, "none"), "image 20x10 does not match the calibration 40x30");
  o = options();
  o.calibration = dir_ / "nowhere";
  expectError(good_, "calibration folder or file does not exist", o, o.calibration);
}

TEST_F(BrokenBag, StrictTopicMap) {
  ReadOptions o = options();
  o.bag_topics = dir_ / "typo.yaml";
  writeBytes(o.bag_topics, "imu: /imu0\ncamra: /cam0/image_raw\n");
  expectError(good_, "camra", o, o.bag_topics);
  writeBytes(o.bag_topics, "imu: [1, 2]\n");
  expectError(good_, "imu", o, o.bag_topics);
  writeBytes(o.bag_topics, "thrust_axis: [0, 0, 2]\n");
  expectError(good_, "thrust_axis must be a unit vector", o, o.bag_topics);
  // A topic map for a non-bag input is an error, not silently ignored.
  try {
    readSequence(dir_ / "asl", options());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(e.problem().find("applies to ROS bags only"), std::string::npos) << e.what();
  }
}

// Random single-byte corruptions (fixed seed): reading either succeeds or throws InputError;
// nothing crashes and no other exception escapes, also when loading the images afterwards.
TEST_F(BrokenBag, CorruptedBytesAreInputErrorsOrHarmless) {
  std::mt19937 rng(20);
  int errors = 0, read = 0;
  for (const std::string& good : {good_, test::flightBag(flight_, "lz4")}) {
    std::uniform_int_distribution<std::size_t> at(0, good.size() - 1);
    for (int i = 0; i < 150; ++i) {
      std::string bad = good;
      bad[at(rng)] = static_cast<char>(rng());
      const std::string bag = dir_ / "mutated.bag";
      writeBytes(bag, bad);
      try {
        const Sequence seq = readSequence(bag, options());
        for (const auto& image : seq.images) loadImage(image);
        ++read;
      } catch (const InputError&) {
        ++errors;
      } catch (const std::exception& e) {
        ADD_FAILURE() << "not an InputError: " << e.what();
      }
    }
  }
  std::printf("corrupted bags: %d InputErrors, %d read\n", errors, read);
  EXPECT_GT(errors, 0);
  EXPECT_GT(read, 0);  // most bytes are sample values, which any number may replace
}

TEST_F(BrokenBag, ToolsExitTwoWithOneLineAndNoOutput) {
  const std::string bag = dir_ / "cut.bag";
  writeBytes(bag, good_.substr(0, good_.size() / 2));
  const std::string out = dir_ / "out";
  auto o = hdvio::test::runCommand(std::string(HDVIO_CONVERT_BIN) + " --input " + bag + " --topics " +
                                   (dir_ / "topics.yaml") + " --calibration " + (dir_ / "asl/mav0") + " --output " + out);
  EXPECT_EQ(o.exit_code, 2) << o.output;
  EXPECT_EQ(o.output.rfind("error: " + bag + ": truncated bag: ", 0), 0u) << o.output;
  EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << o.output;
  EXPECT_FALSE(fs::exists(out));
  o = hdvio::test::runCommand(std::string(HDVIO_INFO_BIN) + " " + bag);
  EXPECT_EQ(o.exit_code, 2) << o.output;
}

}  // namespace
}  // namespace hdvio::io
