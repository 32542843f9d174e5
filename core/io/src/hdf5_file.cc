#include "hdf5_file.h"

#include <hdf5.h>

#include <cmath>
#include <filesystem>

#include "hdvio/core/error.h"

namespace hdvio::io {
namespace {

herr_t collectName(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}

// libhdf5 1.10 trusts a dataset's layout message: a compact or contiguous dataset whose stored
// bytes are fewer than its shape needs (or lie past the end of the file) is copied out of bounds
// inside H5Dread, a segfault rather than an error. Chunked datasets are read chunk by chunk
// through the chunk index, which libhdf5 checks itself.
bool storageMatchesShape(hid_t d, hid_t space, hid_t type, std::uintmax_t file_size) {
  const hid_t dcpl = H5Dget_create_plist(d);
  const H5D_layout_t layout = H5Pget_layout(dcpl);
  H5Pclose(dcpl);
  if (layout == H5D_CHUNKED) return true;
  if (layout != H5D_COMPACT && layout != H5D_CONTIGUOUS) return false;
  const hssize_t points = H5Sget_simple_extent_npoints(space);
  const std::size_t value_size = H5Tget_size(type);
  if (points < 0 || value_size == 0) return false;
  const hsize_t stored = H5Dget_storage_size(d);
  if (layout == H5D_CONTIGUOUS) {
    const haddr_t offset = H5Dget_offset(d);
    if (offset == HADDR_UNDEF) return stored == 0;  // never written: libhdf5 returns fill values
    if (offset > file_size || stored > file_size - offset) return false;
  }
  return stored == static_cast<hsize_t>(points) * value_size;
}

}  // namespace

Hdf5File::Hdf5File(const std::string& path) : path_(path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, 0, "no such file");
  file_size_ = std::filesystem::file_size(path);
  htri_t is_hdf5 = -1;
  hid_t id = -1;
  H5E_BEGIN_TRY {
    is_hdf5 = H5Fis_hdf5(path.c_str());
    if (is_hdf5 > 0) id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  }
  H5E_END_TRY;
  if (is_hdf5 <= 0) throw InputError(path, 0, "not an HDF5 file");
  if (id < 0) throw InputError(path, 0, "cannot open HDF5 file");
  id_ = id;
}

Hdf5File::~Hdf5File() {
  if (id_ >= 0) H5Fclose(static_cast<hid_t>(id_));
}

bool Hdf5File::has(const std::string& dataset) const {
  htri_t exists = 0;
  H5E_BEGIN_TRY { exists = H5Lexists(static_cast<hid_t>(id_), dataset.c_str(), H5P_DEFAULT); }
  H5E_END_TRY;
  return exists > 0;
}

std::vector<std::string> Hdf5File::datasets() const {
  std::vector<std::string> names;
  // A damaged link table ends the listing; the reader then names what it found (libhdf5's own
  // error stack would only repeat that on stderr).
  H5E_BEGIN_TRY { H5Literate(static_cast<hid_t>(id_), H5_INDEX_NAME, H5_ITER_INC, nullptr, collectName, &names); }
  H5E_END_TRY;
  return names;
}

Hdf5Matrix Hdf5File::read(const std::string& name) const {
  if (!has(name)) throw InputError(path_, 0, "missing dataset '" + name + "'");
  // A chunked dataset that was never written can declare any shape in a few bytes of file;
  // its values are allocated here, so the shape is bounded (DIDO's longest flight: ~1e6).
  constexpr hsize_t kMaxValues = hsize_t{1} << 25;  // 256 MiB as doubles
  Hdf5Matrix m;
  bool ok = false;
  bool too_large = false;
  bool damaged = false;
  int ndims = -1;
  H5E_BEGIN_TRY {
    const hid_t d = H5Dopen2(static_cast<hid_t>(id_), name.c_str(), H5P_DEFAULT);
    if (d >= 0) {
      const hid_t space = H5Dget_space(d);
      const hid_t type = H5Dget_type(d);
      ndims = H5Sget_simple_extent_ndims(space);
      const H5T_class_t cls = H5Tget_class(type);
      hsize_t dims[2] = {0, 1};
      if ((ndims == 1 || ndims == 2) && (cls == H5T_FLOAT || cls == H5T_INTEGER)) {
        H5Sget_simple_extent_dims(space, dims, nullptr);
        m.rows = dims[0];
        m.cols = ndims == 2 ? dims[1] : 1;
        too_large = m.rows > kMaxValues || m.cols > kMaxValues || m.rows * m.cols > kMaxValues;
        damaged = !too_large && !storageMatchesShape(d, space, type, file_size_);
        if (!too_large && !damaged) {
          m.values.resize(m.rows * m.cols);
          ok = m.values.empty() ||
               H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.values.data()) >= 0;
        }
      }
      H5Tclose(type);
      H5Sclose(space);
      H5Dclose(d);
    }
  }
  H5E_END_TRY;
  if (too_large)
    throw InputError(where(name), 0, "dataset of " + std::to_string(m.rows) + " x " + std::to_string(m.cols) +
                                         " values is larger than the readers accept (2^25 values)");
  if (damaged)
    throw InputError(where(name), 0, "damaged dataset: its stored bytes do not match its " + std::to_string(m.rows) +
                                         " x " + std::to_string(m.cols) + " shape (corrupt file?)");
  if (!ok) throw InputError(where(name), 0, "cannot read as a 1-D or 2-D numeric dataset");
  return m;
}

Hdf5Matrix Hdf5File::readChecked(const std::string& name, long rows, std::size_t cols) const {
  Hdf5Matrix m = read(name);
  if (m.cols != cols)
    throw InputError(where(name), 0, "expected " + std::to_string(cols) + " columns, found " + std::to_string(m.cols));
  if (rows >= 0 && m.rows != static_cast<std::size_t>(rows))
    throw InputError(where(name), 0, "expected " + std::to_string(rows) + " rows (as many as 'ts'), found " +
                                         std::to_string(m.rows));
  for (std::size_t i = 0; i < m.values.size(); ++i) {
    if (!std::isfinite(m.values[i]))
      throw InputError(where(name), static_cast<long>(i / cols) + 1, "non-finite value in column " +
                                                                        std::to_string(i % cols + 1));
  }
  return m;
}

}  // namespace hdvio::io
