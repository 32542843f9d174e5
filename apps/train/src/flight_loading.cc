#include "hdvio/train/flight_loading.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "hdvio/io/datasets.h"
#include "hdvio/io/sequence_reader.h"
#include "hdvio/train/estimate_supervision.h"

namespace hdvio::train {

std::string resolvePath(const std::string& root, const std::string& path) {
  if (root.empty() || path.empty() || path[0] == '/') return path;
  return root + "/" + path;
}

std::vector<std::string> splitList(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  for (std::string item; std::getline(ss, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

Sequence loadSequence(const std::string& path, const FlightSource& source) {
  io::ReadOptions options;
  if (source.thrust_coefficient > 0.0) options.thrust_coefficient = source.thrust_coefficient;
  if (source.mass > 0.0) options.mass = source.mass;
  return io::readSequence(resolvePath(source.data_root, path), options);
}

learned::FlightSamples loadFlight(const std::string& path, const FlightSource& source,
                                  const std::string& estimate_dir) {
  learned::ResampleOptions options;
  options.rate_hz = source.rate_hz;
  Sequence seq = loadSequence(path, source);
  if (!estimate_dir.empty()) superviseWithEstimate(resolvePath(source.data_root, estimate_dir), &seq);
  learned::FlightSamples f = learned::resampleFlight(seq, options);
  f.name = path;
  return f;
}

bool isNeuroBemFile(const std::string& path) {
  return path.size() > 4 && path.substr(path.size() - 4) == ".csv" && path.find("neurobem") != std::string::npos;
}

std::vector<Vec3> neuroBemForcesAt(const std::string& path, const FlightSource& source,
                                   const std::vector<Timestamp>& t, double mass) {
  const std::vector<io::NeuroBemForceSample> s = io::readNeuroBemForces(resolvePath(source.data_root, path));
  std::vector<Vec3> out;
  out.reserve(t.size());
  for (Timestamp tk : t) {
    auto hi = std::lower_bound(s.begin(), s.end(), tk, [](const auto& a, Timestamp v) { return a.t < v; });
    if (hi == s.begin() || hi == s.end()) {
      out.push_back((hi == s.end() ? s.back() : *hi).force / mass);
      continue;
    }
    const auto lo = hi - 1;
    const double a = static_cast<double>(tk - lo->t) / static_cast<double>(hi->t - lo->t);
    out.push_back(((1.0 - a) * lo->force + a * hi->force) / mass);
  }
  return out;
}

learned::FlightSamples fractionOf(const learned::FlightSamples& flight, double begin, double end) {
  const double n = static_cast<double>(flight.size());
  return flight.slice(static_cast<std::size_t>(std::floor(begin * n)),
                      static_cast<std::size_t>(std::floor(end * n)));
}

}  // namespace hdvio::train
