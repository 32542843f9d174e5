#include "hdf5_streams.h"

#include <cmath>

#include "hdvio/core/error.h"
#include "stream_checks.h"

namespace hdvio::io {

Timestamp secondsToNs(double seconds) {
  const double whole = std::floor(seconds);
  return static_cast<Timestamp>(whole) * kNanosPerSecond +
         static_cast<Timestamp>(std::llround((seconds - whole) * 1e9));
}

std::vector<Timestamp> stampsFromSeconds(const Hdf5File& file, const Hdf5Matrix& ts) {
  std::vector<Timestamp> out(ts.rows);
  for (std::size_t r = 0; r < ts.rows; ++r) {
    // Converting a double beyond int64's range is undefined, not an error value.
    if (!(std::fabs(ts(r, 0)) < 9.2e9))
      throw InputError(file.where("ts"), static_cast<long>(r) + 1, "time " + std::to_string(ts(r, 0)) + " s out of range");
    out[r] = secondsToNs(ts(r, 0));
  }
  return out;
}

std::vector<std::size_t> orderedRows(const Hdf5File& file, const std::vector<Timestamp>& row_stamps,
                                     const std::vector<const Hdf5Matrix*>& row_data,
                                     std::vector<Timestamp>* stamps, Sequence* seq) {
  TimeOrder order(file.where("ts"), "imu0");
  std::vector<std::size_t> kept;
  for (std::size_t r = 0; r < row_stamps.size(); ++r) {
    const Timestamp t = row_stamps[r];
    bool same = r > 0;
    for (const Hdf5Matrix* m : row_data) {
      for (std::size_t c = 0; same && c < m->cols; ++c) same = (*m)(r, c) == (*m)(r - 1, c);
    }
    if (!order.accept(t, same, static_cast<long>(r) + 1)) continue;
    kept.push_back(r);
    stamps->push_back(t);
  }
  if (order.duplicates() > 0) seq->warnings.push_back(order.warning());
  return kept;
}

void fillImu(const Hdf5File& file, const std::vector<std::size_t>& rows,
             const std::vector<Timestamp>& stamps, const Hdf5Matrix& gyro, const Hdf5Matrix& accel,
             const ReadOptions& options, Sequence* seq) {
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::size_t r = rows[k];
    if (k > 0) checkImuGap(stamps[k - 1], stamps[k], options.max_imu_gap_s, file.where("ts"), static_cast<long>(r) + 1);
    ImuSample s;
    s.t = stamps[k];
    s.gyro = Vec3(gyro(r, 0), gyro(r, 1), gyro(r, 2));
    s.accel = Vec3(accel(r, 0), accel(r, 1), accel(r, 2));
    seq->imu.push_back(s);
  }
  if (seq->imu.empty()) throw InputError(file.where("ts"), 0, "no IMU samples");
}

}  // namespace hdvio::io
