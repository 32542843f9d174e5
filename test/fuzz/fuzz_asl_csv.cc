// Fuzzes the CSV cursor (csv.cc) and the ASL stream readers (asl_reader.cc). The first byte
// picks which file of an otherwise valid ASL folder the remaining bytes become; mode 0 reads
// the bytes as a blank-separated text trajectory through every CsvReader field accessor.
#include <cstdint>
#include <string>

#include "fuzz_common.h"
#include "hdvio/core/error.h"
#include "hdvio/io/asl.h"
#include "hdvio/io/csv.h"

namespace fs = std::filesystem;
using namespace hdvio;

namespace {

const char* kImuCsv =
    "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n"
    "1000000000,0.1,0.2,0.3,9.8,0.1,0.2\n"
    "1005000000,0.1,0.2,0.3,9.8,0.1,0.2\n"
    "1010000000,0.1,0.2,0.3,9.8,0.1,0.2\n";

// mode -> the file the input replaces (relative to <scratch>/m<mode>/mav0).
const char* kTargets[] = {
    nullptr,  // CsvReader on its own
    "imu0/data.csv",
    "cam0/data.csv",
    "state_groundtruth_estimate0/data.csv",
    "thrust0/data.csv",
    "rotor0/data.csv",
    "force_groundtruth0/data.csv",
    "landmarks0/data.csv",
    "landmarks0/points.csv",
};
constexpr int kModes = sizeof(kTargets) / sizeof(kTargets[0]);

fs::path folder(int mode) { return hdvio::fuzz::scratch() / ("m" + std::to_string(mode)); }

// Every other file of each mode's folder, valid, written once.
void prepare() {
  for (int mode = 1; mode < kModes; ++mode) {
    const fs::path mav0 = folder(mode) / "mav0";
    fuzz::writeFile(mav0 / "imu0/data.csv", kImuCsv);
    const std::string t = kTargets[mode];
    const std::string stream = t.substr(0, t.find('/'));
    if (stream == "cam0") fuzz::writeFile(mav0 / "cam0/sensor.yaml", fuzz::kCameraYaml);
    if (stream == "thrust0") fuzz::writeFile(mav0 / t, "#t,x,y,z\n");
    if (stream == "rotor0") fuzz::writeFile(mav0 / t, "#t,w1,w2,w3,w4\n");
    if (stream == "landmarks0") {
      fuzz::writeFile(mav0 / "landmarks0/points.csv", "#id,x,y,z\n0,1,2,3\n1,4,5,6\n");
      fuzz::writeFile(mav0 / "landmarks0/data.csv", "#t,id,u,v\n1000000000,0,10,20\n");
    }
    fs::create_directories((mav0 / t).parent_path());
  }
}

void readEveryField(const std::string& path, char delimiter) {
  io::CsvReader csv(path, delimiter);
  csv.readHeader(delimiter == ',');
  while (csv.next()) {
    (void)csv.rowText();
    for (std::size_t i = 0; i < csv.size(); ++i) {
      for (int accessor = 0; accessor < 5; ++accessor) {
        try {
          switch (accessor) {
            case 0: (void)csv.number(i); break;
            case 1: (void)csv.integer(i); break;
            case 2: (void)csv.timestampNs(i); break;
            case 3: (void)csv.secondsAsNs(i); break;
            case 4: (void)csv.text(i); break;
          }
        } catch (const InputError&) {
        }
      }
    }
    try {
      csv.expectColumns(3);
    } catch (const InputError&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  prepare();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const int mode = data[0] % kModes;
  const std::string bytes = fuzz::bytesOf(data + 1, size - 1);
  try {
    if (mode == 0) {
      const std::string path = fuzz::writeFile(fuzz::scratch() / "text.csv", bytes);
      readEveryField(path, (data[0] / kModes) % 2 ? ' ' : ',');
      return 0;
    }
    fuzz::writeFile(folder(mode) / "mav0" / kTargets[mode], bytes);
    io::ReadOptions options;
    options.check_images_exist = false;
    options.max_imu_gap_s = 1e6;  // let any spacing through to the rest of the checks
    const Sequence seq = io::readAsl(folder(mode).string(), options);
    (void)seq;
  } catch (const InputError&) {
  }
  return 0;
}
