#pragma once
// Shared by the fuzz targets: a per-process scratch folder, file writing, and the fixed valid
// calibration the targets place next to the fuzzed file. A reader may reject an input only
// with the exceptions it documents (InputError); anything else escapes LLVMFuzzerTestOneInput,
// and libFuzzer reports it as a crash.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace hdvio::fuzz {

// /tmp/hdvio_fuzz_<pid>: each fuzzing process (and each -fork/-jobs worker) has its own.
inline const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    const auto p = std::filesystem::temp_directory_path() / ("hdvio_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(p);
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(scratch(), ignored);
    });
    return p;
  }();
  return dir;
}

inline std::string writeFile(const std::filesystem::path& path, const std::string& bytes) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path.string();
}

inline std::string bytesOf(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// A valid EuRoC-style sensor.yaml for the camera (752x480, radial-tangential) and the IMU.
inline const char* kCameraYaml =
    "%YAML:1.0\nsensor_type: camera\nT_BS:\n  cols: 4\n  rows: 4\n"
    "  data: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n"
    "rate_hz: 20\nresolution: [752, 480]\ncamera_model: pinhole\n"
    "intrinsics: [458.654, 457.296, 367.215, 248.375]\ndistortion_model: radial-tangential\n"
    "distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n";
inline const char* kImuYaml =
    "%YAML:1.0\nsensor_type: imu\nT_BS:\n  cols: 4\n  rows: 4\n"
    "  data: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n"
    "rate_hz: 200\ngyroscope_noise_density: 1.7e-4\ngyroscope_random_walk: 1.9e-5\n"
    "accelerometer_noise_density: 2.0e-3\naccelerometer_random_walk: 3.0e-3\n";

}  // namespace hdvio::fuzz
