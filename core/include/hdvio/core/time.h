#pragma once
// Time in hdvio is int64 nanoseconds since an arbitrary epoch (the datasets' own clocks).
#include <cstdint>
#include <cmath>

namespace hdvio {

using Timestamp = std::int64_t;  // nanoseconds

constexpr Timestamp kNanosPerSecond = 1000000000LL;

inline double toSeconds(Timestamp t) { return static_cast<double>(t) * 1e-9; }
inline Timestamp fromSeconds(double s) { return static_cast<Timestamp>(std::llround(s * 1e9)); }
// Difference of two timestamps in seconds, exact for spans under ~100 days.
inline double secondsBetween(Timestamp a, Timestamp b) { return static_cast<double>(b - a) * 1e-9; }

}  // namespace hdvio
