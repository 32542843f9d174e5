#pragma once
// Cross-validation folds. Leave-one-flight-out: fold i trains on every flight but the i-th and
// tests on the i-th, so each flight is unseen exactly once and the folds decide the model
// choice. Contiguous blocks of one flight: fold i tests on the i-th of k equal blocks and trains
// on the rest minus a gap on each side of the test block (windows are cut inside each range, so
// none overlaps the test block; the gap keeps the neighbouring, correlated seconds out too).
#include <cstddef>
#include <string>
#include <vector>

namespace hdvio::learned {

struct FlightFold {
  std::vector<std::string> train;  // in the given order, without the test flight
  std::string test;
};

// Throws std::invalid_argument for fewer than two flights, a repeated flight or a fold
// index outside [0, flights.size()).
FlightFold leaveOneFlightOut(const std::vector<std::string>& flights, int fold);

struct SampleRange {
  std::size_t begin = 0;  // [begin, end) sample indices
  std::size_t end = 0;
};

struct BlockFold {
  std::vector<SampleRange> train;  // one or two ranges (before / after the test block)
  SampleRange test;
};

// Block i of k is [i n / k, (i+1) n / k); the training ranges end `gap` samples before it and
// start `gap` samples after it (empty ranges are dropped). Throws std::invalid_argument for
// k < 2, a fold outside [0, k) or blocks shorter than gap + 1 samples.
BlockFold contiguousBlockFold(std::size_t samples, int folds, int fold, std::size_t gap);

}  // namespace hdvio::learned
