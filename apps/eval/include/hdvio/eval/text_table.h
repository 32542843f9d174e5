#pragma once
// Line-by-line numeric text parsing shared by the trajectory readers. Every problem becomes an
// InputError naming file and line, so a malformed file never yields a partial trajectory.
#include <string>
#include <vector>

#include "hdvio/core/time.h"

namespace hdvio::eval {

struct NumericRow {
  long line = 0;                     // 1-based line number in the file
  std::vector<std::string> fields;   // raw tokens
};

struct NumericTable {
  std::string file;
  std::vector<std::string> comments;  // lines starting with '#', in order
  std::vector<NumericRow> rows;
};

// Reads a text file whose data lines are separated by whitespace and/or commas. Empty lines are
// skipped; '#' lines are kept as comments. Throws InputError if the file cannot be opened.
NumericTable readNumericTable(const std::string& path);

// Parses one field as a finite double; throws InputError(file, line, ...) otherwise.
double parseFinite(const std::string& file, long line, const std::string& field);

// Parses a time in seconds ("1525745895.001626729965", "12", "1.4e9") to integer ns without the
// rounding a double would introduce for epoch-sized values.
Timestamp parseSecondsAsNanos(const std::string& file, long line, const std::string& field);

// Parses an integer nanosecond stamp ("1403715273262142976").
Timestamp parseNanos(const std::string& file, long line, const std::string& field);

// Requires strictly increasing stamps; names the first offending line.
void requireIncreasing(const std::string& file, const std::vector<Timestamp>& t,
                       const std::vector<long>& lines);

// Requires stamps that never go backwards and returns how many repeat the previous stamp. Used
// for trajectories, which evo reads without checking order: it keeps every pose of a repeated
// stamp (ORB-SLAM writes some twice), while a backwards step is a broken file.
std::size_t requireNonDecreasing(const std::string& file, const std::vector<Timestamp>& t,
                                 const std::vector<long>& lines);

}  // namespace hdvio::eval
