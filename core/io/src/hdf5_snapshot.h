#pragma once
// Every top-level dataset of an HDF5 file, read by libhdf5 in a child process.
//
// libhdf5 1.10 trusts sizes in a damaged file's metadata (local heaps, layout messages) and can
// crash instead of returning an error (fuzz_hdf5_raw found null reads and writes in H5Dread and
// in symbol-table lookups). A crash in the child is an InputError in the caller; the caller's
// process never runs libhdf5.
#include <string>
#include <vector>

namespace hdvio::io {

struct Hdf5Entry {
  std::string name;
  std::size_t rows = 0, cols = 0;  // cols == 1 for a 1-D dataset
  std::vector<double> values;      // row-major; empty unless problem is empty
  std::string problem;             // why it cannot be read as a 1-D / 2-D numeric dataset
};

// Throws InputError(path, 0, ...) when the file is not HDF5, cannot be opened, or libhdf5
// crashed reading it.
std::vector<Hdf5Entry> readHdf5Snapshot(const std::string& path);

}  // namespace hdvio::io
