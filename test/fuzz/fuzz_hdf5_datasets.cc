// Fuzzes the project's checks in the Blackbird and DIDO readers (blackbird_reader.cc,
// dido_reader.cc, hdf5_file.cc, hdf5_streams.cc) on well-formed HDF5 files with fuzzed
// contents: the input bytes are a recipe (FuzzedDataProvider) for the datasets of a file:
// which names, rank, shape (up to 2^40 rows in chunked, never-written storage), element type
// and values (ramps, specials, raw doubles); for Blackbird, the leftover bytes become
// stamped_groundtruth_imu.txt. libhdf5's own parser is not the target (fuzz_hdf5_raw is).
#include <fuzzer/FuzzedDataProvider.h>
#include <hdf5.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "fuzz_common.h"
#include "hdvio/core/error.h"
#include "hdvio/io/datasets.h"

namespace fs = std::filesystem;
using namespace hdvio;

namespace {

const char* kNames[] = {"ts", "gyro_calib", "accel_calib", "thrust", "gyr", "acc", "meas_rpm",
                        "gt_p", "gt_v", "gt_q", "other", "ts"};

double special(FuzzedDataProvider& p) {
  const double values[] = {0.0, 1.0, -1.0, 0.5, 1.5e9, -1.5e9, 9.3e9, 1e300, -1e300,
                           std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::max(), std::numeric_limits<double>::lowest(),
                           std::numeric_limits<double>::denorm_min()};
  return values[p.ConsumeIntegralInRange<std::size_t>(0, sizeof(values) / sizeof(values[0]) - 1)];
}

std::vector<double> values(FuzzedDataProvider& p, std::size_t n, hsize_t cols) {
  std::vector<double> v(n);
  switch (p.ConsumeIntegralInRange(0, 3)) {
    case 0: {  // a ramp per column, like timestamps and smooth signals
      std::vector<double> start(cols), step(cols);
      for (hsize_t c = 0; c < cols; ++c) {
        start[c] = p.ConsumeBool() ? special(p) : p.ConsumeFloatingPoint<double>();
        step[c] = p.ConsumeBool() ? 0.01 : p.ConsumeFloatingPoint<double>();
      }
      for (std::size_t i = 0; i < n; ++i) v[i] = start[i % cols] + static_cast<double>(i / cols) * step[i % cols];
      break;
    }
    case 1:
      for (double& x : v) x = special(p);
      break;
    case 2:
      for (double& x : v) x = p.ConsumeFloatingPoint<double>();
      break;
    default: {  // unit quaternions (w, x, y, z) with an occasional bad one
      for (std::size_t i = 0; i < n; ++i) v[i] = i % cols == 0 ? 1.0 : 0.0;
      if (n > 0 && p.ConsumeBool()) v[p.ConsumeIntegralInRange<std::size_t>(0, n - 1)] = special(p);
      break;
    }
  }
  return v;
}

hid_t fileType(FuzzedDataProvider& p) {
  switch (p.ConsumeIntegralInRange(0, 5)) {
    case 0: return H5T_IEEE_F64LE;
    case 1: return H5T_IEEE_F32LE;
    case 2: return H5T_STD_I32LE;
    case 3: return H5T_STD_U8LE;
    case 4: return H5T_IEEE_F64BE;
    default: return H5T_C_S1;  // a string: not numeric
  }
}

void addDataset(hid_t file, FuzzedDataProvider& p) {
  const char* name = kNames[p.ConsumeIntegralInRange<std::size_t>(0, sizeof(kNames) / sizeof(kNames[0]) - 1)];
  const int rank = p.ConsumeIntegralInRange(0, 3);
  const bool huge = p.ConsumeIntegralInRange(0, 15) == 0;  // a shape far larger than the file
  hsize_t dims[3] = {1, 1, 1};
  std::size_t n = 1;
  for (int i = 0; i < rank; ++i) {
    dims[i] = huge && i == 0 ? p.ConsumeIntegralInRange<hsize_t>(1, hsize_t{1} << 40)
                             : p.ConsumeIntegralInRange<hsize_t>(0, i == 0 ? 64 : 6);
    n *= dims[i];
  }
  const hid_t space = rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(rank, dims, nullptr);
  const hid_t type = fileType(p);
  const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  if (huge) {
    hsize_t chunk[3];
    for (int i = 0; i < rank; ++i) chunk[i] = std::max<hsize_t>(1, std::min<hsize_t>(dims[i], 64));
    H5Pset_chunk(dcpl, rank, chunk);
  }
  const hid_t d = H5Dcreate2(file, name, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  const hsize_t cols = rank >= 2 ? dims[1] : 1;
  if (d >= 0 && !huge && n > 0 && type != H5T_C_S1) {
    const std::vector<double> v = values(p, n, std::max<hsize_t>(cols, 1));
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  }
  if (d >= 0) H5Dclose(d);
  H5Pclose(dcpl);
  H5Sclose(space);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // the readers report errors themselves
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider p(data, size);
  const bool dido = p.ConsumeBool();
  const fs::path folder = fuzz::scratch() / "h5" / "seq";
  fs::create_directories(folder);
  const std::string h5 = (folder / "data.hdf5").string();
  const hid_t file = H5Fcreate(h5.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (file < 0) return 0;
  const int datasets = p.ConsumeIntegralInRange(0, 10);
  for (int i = 0; i < datasets; ++i) addDataset(file, p);
  H5Fclose(file);
  const fs::path gt = folder / "stamped_groundtruth_imu.txt";
  if (!dido && p.ConsumeBool()) fuzz::writeFile(gt, p.ConsumeRemainingBytesAsString());
  else fs::remove(gt);
  try {
    io::ReadOptions options;
    if (p.ConsumeBool()) options.max_imu_gap_s = 1e6;
    if (dido) (void)io::readDido(folder.string(), options);
    else (void)io::readBlackbird(folder.string(), options);
  } catch (const InputError&) {
  }
  return 0;
}
