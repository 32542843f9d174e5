#pragma once
// Writes one row-major double dataset (1-D when cols == 1): the tests' and the fuzz seeds' way
// to build small Blackbird / DIDO layout files.
#include <hdf5.h>

#include <vector>

namespace hdvio::io::test {

inline void writeDataset(hid_t file, const char* name, const std::vector<double>& v, hsize_t cols) {
  const hsize_t dims[2] = {v.size() / cols, cols};
  const hid_t space = H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr);
  const hid_t d = H5Dcreate2(file, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Dclose(d);
  H5Sclose(space);
}

}  // namespace hdvio::io::test
