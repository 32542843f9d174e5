#pragma once
// Minimal read-only access to the 1-D / 2-D float datasets of the Blackbird and DIDO files. The
// file is read once, whole, by libhdf5 in a child process (hdf5_snapshot.h): a damaged file that
// crashes libhdf5 is an InputError, not a crash of the reader's program.
#include <string>
#include <vector>

#include "hdf5_snapshot.h"

namespace hdvio::io {

// Row-major matrix read from a dataset; a 1-D dataset has cols == 1.
struct Hdf5Matrix {
  std::size_t rows = 0;
  std::size_t cols = 0;
  std::vector<double> values;
  double operator()(std::size_t r, std::size_t c) const { return values[r * cols + c]; }
};

class Hdf5File {
 public:
  // Throws InputError if path is missing or not an HDF5 file.
  explicit Hdf5File(const std::string& path);

  bool has(const std::string& dataset) const;
  std::vector<std::string> datasets() const;  // top-level names
  // Reads a numeric dataset; throws unless it exists and is 1-D or 2-D.
  Hdf5Matrix read(const std::string& dataset) const;
  // As read(), also requiring the given shape (cols; rows when rows >= 0) and finite values.
  Hdf5Matrix readChecked(const std::string& dataset, long rows, std::size_t cols) const;
  const std::string& path() const { return path_; }
  // "file.hdf5[dataset]", used as the file part of InputErrors.
  std::string where(const std::string& dataset) const { return path_ + "[" + dataset + "]"; }

 private:
  const Hdf5Entry* find(const std::string& dataset) const;

  std::string path_;
  std::vector<Hdf5Entry> entries_;
};

}  // namespace hdvio::io
