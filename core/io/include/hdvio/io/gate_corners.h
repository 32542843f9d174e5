#pragma once
// Known race-gate corners and their pixel detections (simulated race flights; docs/gate_io.md):
//   <mav0>/gates0/gates.csv           #gate_id,corner_id,x [m],y [m],z [m]      (world frame)
//   <mav0>/gate_corners0/data.csv     #timestamp [ns],gate_id,corner_id,u [px],v [px]
// Pixels are distorted image coordinates of cam0 (pixel centres at integers, like landmarks0).
// Reading is strict: malformed rows, non-finite numbers, duplicate corners, detections of
// unknown corners and decreasing timestamps are InputErrors naming file and line.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "hdvio/core/lie.h"
#include "hdvio/core/time.h"

namespace hdvio::io {

constexpr int kCornersPerGate = 4;

// Corner (gate_id, corner_id) -> world position.
using GateCornerMap = std::map<std::pair<int, int>, Vec3>;

struct GateCornerDetection {
  Timestamp t = 0;
  int gate_id = 0;
  int corner_id = 0;
  double u = 0.0, v = 0.0;
};

struct GateData {
  GateCornerMap corners;
  std::vector<GateCornerDetection> detections;  // time-ordered
};

GateCornerMap readGateMap(const std::string& path);
std::vector<GateCornerDetection> readGateCorners(const std::string& path, const GateCornerMap& map);

// Both files of an ASL folder (the folder itself or its mav0/). Throws InputError naming the
// missing file when either is absent.
GateData readGateData(const std::string& folder);
bool hasGateData(const std::string& folder);

// Writes both files under <mav0> (created if needed), each through a temporary file + rename.
void writeGateData(const GateData& data, const std::string& mav0_folder);

}  // namespace hdvio::io
