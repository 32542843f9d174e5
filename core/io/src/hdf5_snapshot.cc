#include "hdf5_snapshot.h"

#include <fcntl.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "hdvio/core/error.h"

namespace hdvio::io {
namespace {

enum Status : std::uint64_t { kOk = 0, kNotHdf5 = 1, kCannotOpen = 2 };

// A dataset's declared shape is allocated as is: bounded (DIDO's longest flight: ~1e6 rows).
constexpr hsize_t kMaxValues = hsize_t{1} << 25;  // 256 MiB as doubles

herr_t collectName(hid_t, const char* name, const H5L_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}

// libhdf5 trusts a dataset's layout message: a compact or contiguous dataset whose stored bytes
// are fewer than its shape needs (or lie past the end of the file) is copied out of bounds inside
// H5Dread. Chunked datasets are read through the chunk index, which libhdf5 checks itself.
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

Hdf5Entry readEntry(hid_t file, const std::string& name, std::uintmax_t file_size) {
  Hdf5Entry e;
  e.name = name;
  bool ok = false, too_large = false, damaged = false;
  const hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (d >= 0) {
    const hid_t space = H5Dget_space(d);
    const hid_t type = H5Dget_type(d);
    const int ndims = H5Sget_simple_extent_ndims(space);
    const H5T_class_t cls = H5Tget_class(type);
    hsize_t dims[2] = {0, 1};
    if ((ndims == 1 || ndims == 2) && (cls == H5T_FLOAT || cls == H5T_INTEGER)) {
      H5Sget_simple_extent_dims(space, dims, nullptr);
      e.rows = dims[0];
      e.cols = ndims == 2 ? dims[1] : 1;
      too_large = e.rows > kMaxValues || e.cols > kMaxValues || e.rows * e.cols > kMaxValues;
      damaged = !too_large && !storageMatchesShape(d, space, type, file_size);
      if (!too_large && !damaged) {
        e.values.resize(e.rows * e.cols);
        ok = e.values.empty() ||
             H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, e.values.data()) >= 0;
      }
    }
    H5Tclose(type);
    H5Sclose(space);
    H5Dclose(d);
  }
  const std::string shape = std::to_string(e.rows) + " x " + std::to_string(e.cols);
  if (too_large)
    e.problem = "dataset of " + shape + " values is larger than the readers accept (2^25 values)";
  else if (damaged)
    e.problem = "damaged dataset: its stored bytes do not match its " + shape + " shape (corrupt file?)";
  else if (!ok)
    e.problem = "cannot read as a 1-D or 2-D numeric dataset";
  if (!e.problem.empty()) e.values.clear();
  return e;
}

// The child's side: everything libhdf5 is asked, in-process.
std::vector<Hdf5Entry> readInProcess(const std::string& path, Status* status) {
  std::vector<Hdf5Entry> entries;
  const std::uintmax_t file_size = std::filesystem::file_size(path);
  H5E_BEGIN_TRY {
    const htri_t is_hdf5 = H5Fis_hdf5(path.c_str());
    const hid_t file = is_hdf5 > 0 ? H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT) : -1;
    *status = is_hdf5 <= 0 ? kNotHdf5 : (file < 0 ? kCannotOpen : kOk);
    if (file >= 0) {
      // A damaged link table ends the listing; the readers then name what was found.
      std::vector<std::string> names;
      H5Literate(file, H5_INDEX_NAME, H5_ITER_INC, nullptr, collectName, &names);
      for (const std::string& name : names) entries.push_back(readEntry(file, name, file_size));
      H5Fclose(file);
    }
  }
  H5E_END_TRY;
  return entries;
}

bool writeAll(int fd, const void* data, std::size_t size) {
  const char* bytes = static_cast<const char*>(data);
  for (std::size_t done = 0; done < size;) {
    const ssize_t n = write(fd, bytes + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}
bool writeU64(int fd, std::uint64_t v) { return writeAll(fd, &v, sizeof v); }
bool writeText(int fd, const std::string& s) { return writeU64(fd, s.size()) && writeAll(fd, s.data(), s.size()); }

// The child's answer, streamed: no second copy of the values in either process.
bool writeSnapshot(int fd, Status status, const std::vector<Hdf5Entry>& entries) {
  bool ok = writeU64(fd, status) && writeU64(fd, entries.size());
  for (const Hdf5Entry& e : entries) {
    ok = ok && writeText(fd, e.name) && writeText(fd, e.problem) && writeU64(fd, e.rows) && writeU64(fd, e.cols) &&
         writeU64(fd, e.values.size()) && writeAll(fd, e.values.data(), e.values.size() * sizeof(double));
  }
  return ok;
}

// Reads what the child wrote (trusted: the same program wrote it); false at an early end.
class PipeReader {
 public:
  explicit PipeReader(int fd) : fd_(fd) {}
  bool take(void* dst, std::size_t size) {
    char* out = static_cast<char*>(dst);
    for (std::size_t done = 0; done < size;) {
      const ssize_t n = read(fd_, out + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      done += static_cast<std::size_t>(n);
    }
    return true;
  }
  bool u64(std::uint64_t* v) { return take(v, sizeof *v); }
  bool text(std::string* s) {
    std::uint64_t n = 0;
    if (!u64(&n)) return false;
    s->resize(n);
    return take(s->data(), n);
  }

 private:
  int fd_;
};

bool readSnapshot(int fd, std::uint64_t* status, std::vector<Hdf5Entry>* entries) {
  PipeReader in(fd);
  std::uint64_t count = 0;
  if (!in.u64(status) || !in.u64(&count)) return false;
  for (std::uint64_t i = 0; i < count; ++i) {
    Hdf5Entry e;
    std::uint64_t rows = 0, cols = 0, values = 0;
    if (!in.text(&e.name) || !in.text(&e.problem) || !in.u64(&rows) || !in.u64(&cols) || !in.u64(&values))
      return false;
    e.rows = rows;
    e.cols = cols;
    e.values.resize(values);
    if (!in.take(e.values.data(), values * sizeof(double))) return false;
    entries->push_back(std::move(e));
  }
  return true;
}

}  // namespace

std::vector<Hdf5Entry> readHdf5Snapshot(const std::string& path) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("HDF5 reader: pipe() failed: " + std::string(std::strerror(errno)));
  const pid_t child = fork();
  if (child < 0) {
    close(fds[0]);
    close(fds[1]);
    throw std::runtime_error("HDF5 reader: fork() failed: " + std::string(std::strerror(errno)));
  }
  if (child == 0) {
    close(fds[0]);
    // Nothing the child prints reaches the user (libhdf5's error stack, a sanitizer's report of
    // the crash): the parent turns its end into one error line.
    const int null_fd = open("/dev/null", O_WRONLY);
    if (null_fd >= 0) {
      dup2(null_fd, STDOUT_FILENO);
      dup2(null_fd, STDERR_FILENO);
      close(null_fd);
    }
    Status status = kOk;
    std::vector<Hdf5Entry> entries;
    try {
      entries = readInProcess(path, &status);
    } catch (...) {
      _exit(3);
    }
    _exit(writeSnapshot(fds[1], status, entries) ? 0 : 4);
  }
  close(fds[1]);
  std::uint64_t status = kOk;
  std::vector<Hdf5Entry> entries;
  const bool complete = readSnapshot(fds[0], &status, &entries);
  close(fds[0]);
  int wstatus = 0;
  while (waitpid(child, &wstatus, 0) < 0 && errno == EINTR) {
  }
  // A signal, a sanitizer's exit (it reports a crash and exits with its own code) or an
  // exception in the reader: the file made libhdf5 fail, whatever the build.
  if (WIFSIGNALED(wstatus))
    throw InputError(path, 0, "damaged HDF5 file: libhdf5 crashed reading it (signal " +
                                  std::to_string(WTERMSIG(wstatus)) + ": " + strsignal(WTERMSIG(wstatus)) + ")");
  if (!WIFEXITED(wstatus) || WEXITSTATUS(wstatus) != 0)
    throw InputError(path, 0, "damaged HDF5 file: libhdf5 failed reading it (its reader process ended with code " +
                                  std::to_string(WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1) + ")");
  if (!complete) throw std::runtime_error("HDF5 reader: truncated result from the child process");
  if (status == kNotHdf5) throw InputError(path, 0, "not an HDF5 file");
  if (status == kCannotOpen) throw InputError(path, 0, "cannot open HDF5 file");
  return entries;
}

}  // namespace hdvio::io
