// Fuzzes the sensor.yaml readers (sensor_yaml.cc), Kalibr's calibration files (kalibr_yaml.cc)
// and the bag topic map (the other YAML files a user hands the readers). The first byte picks
// the reader; the rest is the file.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fuzz_common.h"
#include "hdvio/core/error.h"
#include "hdvio/io/ros_bag.h"
#include "kalibr_yaml.h"
#include "sensor_yaml.h"

using namespace hdvio;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string path = fuzz::writeFile(fuzz::scratch() / "sensor.yaml", fuzz::bytesOf(data + 1, size - 1));
  try {
    switch (data[0] % 5) {
      case 0: (void)io::readImuSensorYaml(path); break;
      case 1: {
        const CameraCalibration c = io::readCameraSensorYaml(path);
        // What the reader accepted must pass the check the bag and simulator paths apply.
        try {
          io::validateCamera(c, path);
        } catch (const InputError& e) {
          std::fprintf(stderr, "accepted camera calibration fails validateCamera: %s\n", e.what());
          std::abort();
        }
        break;
      }
      case 2: (void)io::readRotorSensorYaml(path); break;
      case 3: (void)io::readBagTopicMap(path); break;
      case 4: {
        io::KalibrCalibration k;
        io::readKalibrYaml(path, &k);
        if (k.camera) {
          try {
            io::validateCamera(*k.camera, path);
          } catch (const InputError& e) {
            std::fprintf(stderr, "accepted Kalibr camera fails validateCamera: %s\n", e.what());
            std::abort();
          }
        }
        break;
      }
    }
  } catch (const InputError&) {
  }
  return 0;
}
