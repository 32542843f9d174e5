#include "hdvio/io/gate_corners.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "hdvio/core/error.h"
#include "hdvio/io/csv.h"

namespace hdvio::io {
namespace fs = std::filesystem;
namespace {

constexpr const char* kMapFile = "gates0/gates.csv";
constexpr const char* kDetectionFile = "gate_corners0/data.csv";

int idAt(const CsvReader& csv, std::size_t column, const char* what) {
  const long long id = csv.integer(column);
  if (id < 0 || id > 2147483647LL) csv.fail(std::string(what) + " out of range");
  return static_cast<int>(id);
}

void expectHeader(CsvReader* csv, std::size_t columns) {
  const std::vector<std::string> header = csv->readHeader(true);
  if (header.size() != columns)
    throw InputError(csv->path(), csv->line(),
                     "header has " + std::to_string(header.size()) + " columns, expected " +
                         std::to_string(columns));
}

fs::path mav0Of(const std::string& folder) {
  const fs::path root(folder);
  return fs::is_directory(root / "mav0") ? root / "mav0" : root;
}

void writeAtomically(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  const fs::path tmp = file.string() + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw InputError(file.string(), 0, "cannot write file");
  }
  fs::rename(tmp, file);
}

}  // namespace

GateCornerMap readGateMap(const std::string& path) {
  CsvReader csv(path);
  expectHeader(&csv, 5);
  GateCornerMap map;
  while (csv.next()) {
    csv.expectColumns(5);
    const int gate = idAt(csv, 0, "gate_id");
    const int corner = idAt(csv, 1, "corner_id");
    if (corner >= kCornersPerGate) csv.fail("corner_id must be 0..3");
    const Vec3 p(csv.number(2), csv.number(3), csv.number(4));
    if (!map.emplace(std::make_pair(gate, corner), p).second)
      csv.fail("duplicate corner " + std::to_string(gate) + "/" + std::to_string(corner));
  }
  if (map.empty()) throw InputError(path, 0, "no gate corners");
  return map;
}

std::vector<GateCornerDetection> readGateCorners(const std::string& path, const GateCornerMap& map) {
  CsvReader csv(path);
  expectHeader(&csv, 5);
  std::vector<GateCornerDetection> out;
  while (csv.next()) {
    csv.expectColumns(5);
    GateCornerDetection d;
    d.t = csv.timestampNs(0);
    d.gate_id = idAt(csv, 1, "gate_id");
    d.corner_id = idAt(csv, 2, "corner_id");
    d.u = csv.number(3);
    d.v = csv.number(4);
    if (!out.empty() && d.t < out.back().t) csv.fail("non-monotonic timestamp " + std::to_string(d.t));
    if (!map.count({d.gate_id, d.corner_id}))
      csv.fail("gate " + std::to_string(d.gate_id) + " corner " + std::to_string(d.corner_id) +
               " is not in the gate map");
    if (!out.empty() && out.back().t == d.t && out.back().gate_id == d.gate_id &&
        out.back().corner_id == d.corner_id)
      csv.fail("duplicate detection of gate " + std::to_string(d.gate_id) + " corner " +
               std::to_string(d.corner_id));
    out.push_back(d);
  }
  return out;
}

bool hasGateData(const std::string& folder) {
  const fs::path m = mav0Of(folder);
  return fs::exists(m / kMapFile) && fs::exists(m / kDetectionFile);
}

GateData readGateData(const std::string& folder) {
  const fs::path m = mav0Of(folder);
  for (const char* f : {kMapFile, kDetectionFile})
    if (!fs::exists(m / f))
      throw InputError((m / f).string(), 0, "missing (gate map and detections come from a simulated race)");
  GateData data;
  data.corners = readGateMap((m / kMapFile).string());
  data.detections = readGateCorners((m / kDetectionFile).string(), data.corners);
  return data;
}

void writeGateData(const GateData& data, const std::string& mav0_folder) {
  const fs::path m(mav0_folder);
  std::string map = "#gate_id,corner_id,x [m],y [m],z [m]\n";
  for (const auto& [key, p] : data.corners)
    map += std::to_string(key.first) + "," + std::to_string(key.second) + "," + formatDouble(p.x()) + "," +
           formatDouble(p.y()) + "," + formatDouble(p.z()) + "\n";
  std::string det = "#timestamp [ns],gate_id,corner_id,u [px],v [px]\n";
  for (const GateCornerDetection& d : data.detections)
    det += std::to_string(d.t) + "," + std::to_string(d.gate_id) + "," + std::to_string(d.corner_id) + "," +
           formatDouble(d.u) + "," + formatDouble(d.v) + "\n";
  writeAtomically(m / kMapFile, map);
  writeAtomically(m / kDetectionFile, det);
}

}  // namespace hdvio::io
