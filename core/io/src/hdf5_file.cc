#include "hdf5_file.h"

#include <cmath>
#include <filesystem>

#include "hdvio/core/error.h"

namespace hdvio::io {

Hdf5File::Hdf5File(const std::string& path) : path_(path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, 0, "no such file");
  entries_ = readHdf5Snapshot(path);
}

const Hdf5Entry* Hdf5File::find(const std::string& dataset) const {
  for (const Hdf5Entry& e : entries_)
    if (e.name == dataset) return &e;
  return nullptr;
}

bool Hdf5File::has(const std::string& dataset) const { return find(dataset) != nullptr; }

std::vector<std::string> Hdf5File::datasets() const {
  std::vector<std::string> names;
  for (const Hdf5Entry& e : entries_) names.push_back(e.name);
  return names;
}

Hdf5Matrix Hdf5File::read(const std::string& name) const {
  const Hdf5Entry* e = find(name);
  if (!e) throw InputError(path_, 0, "missing dataset '" + name + "'");
  if (!e->problem.empty()) throw InputError(where(name), 0, e->problem);
  return Hdf5Matrix{e->rows, e->cols, e->values};
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
