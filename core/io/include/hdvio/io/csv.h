#pragma once
// A small, fast CSV cursor for the dataset readers: whole file in memory, fields as views,
// numbers through strtod, CRLF tolerated. Every error names the file, the line and the column.
#include <string>
#include <string_view>
#include <vector>

#include "hdvio/core/time.h"

namespace hdvio::io {

class CsvReader {
 public:
  // Throws InputError if the file cannot be read. delimiter ' ' splits on runs of blanks
  // (the space-separated text trajectories); ',' is the CSV default.
  explicit CsvReader(const std::string& path, char delimiter = ',');

  const std::string& path() const { return path_; }

  // Reads the first non-empty line as the header and returns its trimmed column names (a
  // leading '#' is dropped). require_hash: the ASL rule "every CSV starts with one # line".
  std::vector<std::string> readHeader(bool require_hash);

  // Advances to the next non-empty line; false at the end of the file.
  bool next();
  long line() const { return line_; }
  std::size_t size() const { return fields_.size(); }
  std::string_view rowText() const { return row_; }  // without the line ending

  // Throws "expected N columns, found M" unless the row has exactly n fields.
  void expectColumns(std::size_t n) const;

  double number(std::size_t i) const;             // finite double
  long long integer(std::size_t i) const;         // decimal integer
  Timestamp timestampNs(std::size_t i) const;     // integer nanoseconds
  Timestamp secondsAsNs(std::size_t i) const;     // decimal seconds, converted exactly
  std::string_view text(std::size_t i) const;     // trimmed, non-empty

  [[noreturn]] void fail(const std::string& problem) const;

 private:
  std::string columnName(std::size_t i) const;
  [[noreturn]] void failField(std::size_t i, const std::string& problem) const;

  std::string path_;
  char delimiter_ = ',';
  std::string content_;
  std::size_t pos_ = 0;
  long line_ = 0;
  std::string_view row_;
  std::vector<std::string_view> fields_;
  std::vector<std::string> header_;
};

// Exact decimal-seconds -> nanoseconds ("1525745925.001598119736" -> 1525745925001598120).
// Returns false if text is not a plain decimal number (exponents fall back to double rounding).
bool parseSecondsToNs(std::string_view text, Timestamp* ns);

// Full-precision text for a double (round-trips exactly).
std::string formatDouble(double value);

}  // namespace hdvio::io
