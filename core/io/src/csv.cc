#include "hdvio/io/csv.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "hdvio/core/error.h"

namespace hdvio::io {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::string quoted(std::string_view s) {
  constexpr std::size_t kMax = 40;
  std::string out(s.substr(0, kMax));
  if (s.size() > kMax) out += "...";
  return "'" + out + "'";
}

void splitOnBlanks(std::string_view s, std::vector<std::string_view>* out) {
  std::size_t k = 0;
  while (k < s.size()) {
    while (k < s.size() && (s[k] == ' ' || s[k] == '\t')) ++k;
    const std::size_t start = k;
    while (k < s.size() && s[k] != ' ' && s[k] != '\t') ++k;
    if (k > start) out->push_back(s.substr(start, k - start));
  }
}

}  // namespace

CsvReader::CsvReader(const std::string& path, char delimiter) : path_(path), delimiter_(delimiter) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "read error");
  content_ = ss.str();
}

bool CsvReader::next() {
  while (pos_ < content_.size()) {
    const std::size_t end = content_.find('\n', pos_);
    const std::size_t stop = end == std::string::npos ? content_.size() : end;
    std::string_view raw(content_.data() + pos_, stop - pos_);
    pos_ = end == std::string::npos ? content_.size() : end + 1;
    ++line_;
    if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
    if (trim(raw).empty()) continue;
    row_ = raw;
    fields_.clear();
    if (delimiter_ == ' ') {
      splitOnBlanks(trim(raw), &fields_);
      return true;
    }
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = raw.find(delimiter_, start);
      if (comma == std::string_view::npos) {
        fields_.push_back(trim(raw.substr(start)));
        break;
      }
      fields_.push_back(trim(raw.substr(start, comma - start)));
      start = comma + 1;
    }
    return true;
  }
  return false;
}

std::vector<std::string> CsvReader::readHeader(bool require_hash) {
  if (!next()) fail("empty file (expected a header line)");
  std::string_view first = trim(row_);
  if (require_hash && (first.empty() || first.front() != '#'))
    fail("expected a header line starting with '#'");
  header_.clear();
  for (std::size_t i = 0; i < fields_.size(); ++i) {
    std::string_view f = fields_[i];
    if (i == 0 && !f.empty() && f.front() == '#') f = trim(f.substr(1));
    if (i == 0 && f.empty() && delimiter_ == ' ') continue;  // "# ts x y z"
    header_.emplace_back(f);
  }
  return header_;
}

void CsvReader::expectColumns(std::size_t n) const {
  if (fields_.size() != n) {
    fail("expected " + std::to_string(n) + " columns, found " + std::to_string(fields_.size()));
  }
}

std::string CsvReader::columnName(std::size_t i) const {
  std::string s = "column " + std::to_string(i + 1);
  if (i < header_.size() && !header_[i].empty()) s += " (" + header_[i] + ")";
  return s;
}

void CsvReader::fail(const std::string& problem) const { throw InputError(path_, line_, problem); }

void CsvReader::failField(std::size_t i, const std::string& problem) const {
  fail(columnName(i) + ": " + problem);
}

std::string_view CsvReader::text(std::size_t i) const {
  if (i >= fields_.size()) fail("missing " + columnName(i));
  if (fields_[i].empty()) failField(i, "empty field");
  return fields_[i];
}

double CsvReader::number(std::size_t i) const {
  const std::string_view f = text(i);
  // The field is followed by ',', '\r', '\n' or the terminating NUL, all of which stop strtod.
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(f.data(), &end);
  if (end != f.data() + f.size()) failField(i, "not a number: " + quoted(f));
  if (!std::isfinite(v)) failField(i, "non-finite value " + quoted(f));
  return v;
}

long long CsvReader::integer(std::size_t i) const {
  const std::string_view f = text(i);
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(f.data(), &end, 10);
  if (end != f.data() + f.size()) failField(i, "not an integer: " + quoted(f));
  if (errno == ERANGE) failField(i, "integer out of range: " + quoted(f));
  return v;
}

Timestamp CsvReader::timestampNs(std::size_t i) const {
  const std::string_view f = text(i);
  for (char c : f) {
    if ((c < '0' || c > '9') && c != '-') failField(i, "not an integer timestamp [ns]: " + quoted(f));
  }
  return integer(i);
}

Timestamp CsvReader::secondsAsNs(std::size_t i) const {
  Timestamp ns = 0;
  if (parseSecondsToNs(text(i), &ns)) return ns;
  const double s = number(i);
  if (std::fabs(s) > 9.2e9) failField(i, "time out of range");
  return fromSeconds(s);
}

bool parseSecondsToNs(std::string_view text, Timestamp* ns) {
  bool negative = false;
  std::size_t k = 0;
  if (k < text.size() && (text[k] == '-' || text[k] == '+')) negative = text[k++] == '-';
  long long whole = 0;
  int whole_digits = 0;
  while (k < text.size() && text[k] >= '0' && text[k] <= '9') {
    if (++whole_digits > 10) return false;  // beyond int64 ns range
    whole = whole * 10 + (text[k++] - '0');
  }
  long long frac = 0;
  int frac_digits = 0;
  bool round_up = false;
  if (k < text.size() && text[k] == '.') {
    ++k;
    while (k < text.size() && text[k] >= '0' && text[k] <= '9') {
      if (frac_digits < 9) {
        frac = frac * 10 + (text[k] - '0');
        ++frac_digits;
      } else if (frac_digits == 9) {
        round_up = text[k] >= '5';
        ++frac_digits;
      }
      ++k;
    }
  }
  if (k != text.size() || (whole_digits == 0 && frac_digits == 0)) return false;
  // Past this, whole * 1e9 + frac overflows int64; the caller's double fallback then reports
  // the time as out of range.
  constexpr long long kMaxWholeSeconds = (INT64_MAX - kNanosPerSecond) / kNanosPerSecond;
  if (whole > kMaxWholeSeconds) return false;
  for (int d = std::min(frac_digits, 9); d < 9; ++d) frac *= 10;
  Timestamp v = whole * kNanosPerSecond + frac + (round_up ? 1 : 0);
  *ns = negative ? -v : v;
  return true;
}

std::string formatDouble(double value) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.17g", value);
  return buf;
}

}  // namespace hdvio::io
