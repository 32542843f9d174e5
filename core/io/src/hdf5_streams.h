#pragma once
// Shared by the HDF5 readers: seconds -> ns, ordered IMU / ground-truth assembly.
#include <string>
#include <vector>

#include "hdf5_file.h"
#include "hdvio/core/sequence.h"
#include "hdvio/io/read_options.h"

namespace hdvio::io {

// Seconds (double) to integer ns without losing the sub-second digits to a 1e18 product.
Timestamp secondsToNs(double seconds);

// 'ts' converted to ns, one per row; throws unless every time fits int64 ns (|t| < 9.2e9 s).
std::vector<Timestamp> stampsFromSeconds(const Hdf5File& file, const Hdf5Matrix& ts);

// Enforces strictly increasing time (an exact duplicate of the previous
// row over all the given datasets is dropped and counted). Returns the indices of kept rows.
std::vector<std::size_t> orderedRows(const Hdf5File& file, const std::vector<Timestamp>& row_stamps,
                                     const std::vector<const Hdf5Matrix*>& row_data,
                                     std::vector<Timestamp>* stamps, Sequence* seq);

// IMU samples from kept rows, with the gap check.
void fillImu(const Hdf5File& file, const std::vector<std::size_t>& rows,
             const std::vector<Timestamp>& stamps, const Hdf5Matrix& gyro, const Hdf5Matrix& accel,
             const ReadOptions& options, Sequence* seq);

}  // namespace hdvio::io
