#pragma once
// Shared by the learned-model tools: read dataset files through hdvio_io and turn them into
// uniformly resampled FlightSamples, with an optional thrust model for rotor-speed datasets.
#include <string>
#include <vector>

#include "hdvio/learned/flight_samples.h"

namespace hdvio::train {

struct FlightSource {
  std::string data_root;           // prefix for relative paths ("" = as given)
  double thrust_coefficient = 0.0; // N s^2 rad^-2; > 0 derives thrust from rotor speeds
  double mass = 0.0;               // kg; 0 = the dataset's documented mass
  double rate_hz = 100.0;
};

std::string resolvePath(const std::string& root, const std::string& path);
// Splits "a,b,c" into its non-empty parts.
std::vector<std::string> splitList(const std::string& list);

Sequence loadSequence(const std::string& path, const FlightSource& source);
// With estimate_dir (an hdvio_run result folder of this flight) its states are the supervision
// in place of the flight's ground truth (estimate_supervision.h).
learned::FlightSamples loadFlight(const std::string& path, const FlightSource& source,
                                  const std::string& estimate_dir = "");

// NeuroBEM CSV files (their own model's force prediction is a column).
bool isNeuroBemFile(const std::string& path);
// The NeuroBEM model's force (dataset columns, N) at the times t, linearly interpolated and
// divided by mass (mass-normalized like FlightSamples).
std::vector<Vec3> neuroBemForcesAt(const std::string& path, const FlightSource& source,
                                   const std::vector<Timestamp>& t, double mass);

// Samples [floor(begin * n), floor(end * n)) of the flight.
learned::FlightSamples fractionOf(const learned::FlightSamples& flight, double begin, double end);

}  // namespace hdvio::train
