#pragma once
// What a sequence holds and which hdvio methods it can serve (the hdvio_info report).
#include <string>
#include <vector>

#include "hdvio/core/sequence.h"

namespace hdvio::io {

struct AxisRange {
  std::string axis;
  double min = 0.0, max = 0.0;
};

struct StreamSummary {
  std::string name;  // imu0, cam0, thrust0, rotor0, groundtruth, forces, landmarks0
  std::size_t count = 0;
  Timestamp first = 0, last = 0;
  double span_s = 0.0;
  double rate_hz = 0.0;     // 1 / median spacing
  double max_gap_s = 0.0;   // largest spacing
  std::vector<AxisRange> ranges;
};

struct MethodSupport {
  std::string method;
  bool supported = false;
  std::string needs;  // e.g. "imu+cam+thrust"
  std::string missing;
};

struct SequenceSummary {
  std::string name, source;
  // Time all the streams a method would use overlap: IMU, camera and thrust when present.
  double duration_s = 0.0;
  std::vector<StreamSummary> streams;
  double groundtruth_coverage = 0.0;  // fraction of the IMU time span inside the GT span
  std::vector<MethodSupport> methods;
  std::vector<std::string> warnings;
};

SequenceSummary summarize(const Sequence& sequence);
std::string formatSummary(const SequenceSummary& summary);

}  // namespace hdvio::io
