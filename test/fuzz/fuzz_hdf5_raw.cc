// Feeds raw bytes as data.hdf5 to the Blackbird and DIDO readers: this mostly fuzzes libhdf5's
// own file parser (not the project's code); it is here to tell whether libhdf5 survives
// garbage. fuzz_hdf5_datasets fuzzes the project's checks on well-formed files.
#include <hdf5.h>

#include <cstdint>
#include <string>

#include "fuzz_common.h"
#include "hdvio/core/error.h"
#include "hdvio/io/datasets.h"

using namespace hdvio;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::writeFile(fuzz::scratch() / "raw/data.hdf5", fuzz::bytesOf(data, size));
  try {
    (void)io::readBlackbird(path);
  } catch (const InputError&) {
  }
  try {
    (void)io::readDido(path);
  } catch (const InputError&) {
  }
  return 0;
}
