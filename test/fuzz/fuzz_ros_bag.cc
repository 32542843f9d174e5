// Fuzzes the ROS 1 bag container (bag_format.cc, bag_compression.cc) and the bag reader
// (bag_reader.cc): the input is the bag file. scanBag runs on an in-memory stream, and every
// message it reports must be read back identically through its span by readMessage; then
// readRosBag reads the same bytes from a file, with a valid calibration folder.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "bag_format.h"
#include "fuzz_common.h"
#include "hdvio/core/error.h"
#include "hdvio/io/ros_bag.h"

using namespace hdvio;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::writeFile(fuzz::scratch() / "calib/cam0/sensor.yaml", fuzz::kCameraYaml);
  fuzz::writeFile(fuzz::scratch() / "calib/imu0/sensor.yaml", fuzz::kImuYaml);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes = fuzz::bytesOf(data, size);
  try {
    std::istringstream in(bytes);
    std::istringstream again(bytes);
    io::bag::scanBag(in, "fuzz.bag", [&](const io::bag::Message& m) {
      const std::string back = io::bag::readMessage(again, m.span, "fuzz.bag");
      if (back != m.data) {
        std::fprintf(stderr, "readMessage disagrees with scanBag at chunk %llu offset %llu\n",
                     static_cast<unsigned long long>(m.span.chunk_pos), static_cast<unsigned long long>(m.span.offset));
        std::abort();
      }
    });
  } catch (const InputError&) {
  }
  try {
    const std::string path = fuzz::writeFile(fuzz::scratch() / "fuzz.bag", bytes);
    io::ReadOptions options;
    options.calibration = (fuzz::scratch() / "calib").string();
    options.max_imu_gap_s = 1e6;
    (void)io::readRosBag(path, options);
  } catch (const InputError&) {
  }
  return 0;
}
