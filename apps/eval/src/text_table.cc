#include "hdvio/eval/text_table.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>

#include "hdvio/core/error.h"

namespace hdvio::eval {
namespace {

std::string trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const std::size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

// CSV lines split on commas (an empty field stays, so it is reported); other lines on spaces.
std::vector<std::string> tokenize(const std::string& line) {
  std::vector<std::string> fields;
  if (line.find(',') != std::string::npos) {
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line.find(',', start);
      fields.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos
                                                                          : comma - start)));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    return fields;
  }
  std::string current;
  for (char c : line) {
    if (std::isspace(static_cast<unsigned char>(c))) {
      if (!current.empty()) fields.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  if (!current.empty()) fields.push_back(current);
  return fields;
}

bool isBlank(const std::string& s) {
  for (char c : s)
    if (!std::isspace(static_cast<unsigned char>(c))) return false;
  return true;
}

}  // namespace

NumericTable readNumericTable(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open file");
  NumericTable table;
  table.file = path;
  std::string line;
  long number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (isBlank(line)) continue;
    std::size_t first = line.find_first_not_of(" \t");
    if (line[first] == '#') {
      table.comments.push_back(line);
      continue;
    }
    table.rows.push_back({number, tokenize(line)});
  }
  if (in.bad()) throw InputError(path, number, "read error");
  return table;
}

double parseFinite(const std::string& file, long line, const std::string& field) {
  if (field.empty()) throw InputError(file, line, "empty field");
  errno = 0;
  char* end = nullptr;
  const double value = std::strtod(field.c_str(), &end);
  if (end != field.c_str() + field.size())
    throw InputError(file, line, "not a number: '" + field + "'");
  if (!std::isfinite(value)) throw InputError(file, line, "non-finite value: '" + field + "'");
  return value;
}

Timestamp parseNanos(const std::string& file, long line, const std::string& field) {
  if (field.empty()) throw InputError(file, line, "empty timestamp");
  std::size_t start = field[0] == '-' ? 1 : 0;
  bool digits = field.size() > start;
  for (std::size_t i = start; i < field.size(); ++i)
    digits = digits && std::isdigit(static_cast<unsigned char>(field[i]));
  if (!digits) throw InputError(file, line, "timestamp is not an integer of ns: '" + field + "'");
  errno = 0;
  const long long value = std::strtoll(field.c_str(), nullptr, 10);
  if (errno == ERANGE) throw InputError(file, line, "timestamp out of range: '" + field + "'");
  return static_cast<Timestamp>(value);
}

Timestamp parseSecondsAsNanos(const std::string& file, long line, const std::string& field) {
  // Exact path for plain decimals: integer part and first 9 fraction digits, rounded on the 10th.
  bool plain = !field.empty();
  int dots = 0;
  for (std::size_t i = 0; i < field.size(); ++i) {
    const char c = field[i];
    if (c == '.') ++dots;
    else if (!std::isdigit(static_cast<unsigned char>(c)) && !(i == 0 && c == '-')) plain = false;
  }
  if (plain && dots <= 1 && field != "-" && field != "." && field != "-.") {
    const bool negative = field[0] == '-';
    const std::string body = negative ? field.substr(1) : field;
    const std::size_t dot = body.find('.');
    const std::string whole = dot == std::string::npos ? body : body.substr(0, dot);
    std::string frac = dot == std::string::npos ? "" : body.substr(dot + 1);
    if (whole.size() > 10) throw InputError(file, line, "timestamp out of range: '" + field + "'");
    long long ns = whole.empty() ? 0 : std::stoll(whole) * kNanosPerSecond;
    const bool round_up = frac.size() > 9 && frac[9] >= '5';
    frac = frac.substr(0, std::min<std::size_t>(9, frac.size()));
    frac.append(9 - frac.size(), '0');
    ns += std::stoll(frac) + (round_up ? 1 : 0);
    return negative ? -ns : ns;
  }
  const double seconds = parseFinite(file, line, field);
  if (std::fabs(seconds) > 9.0e9) throw InputError(file, line, "timestamp out of range: '" + field + "'");
  return fromSeconds(seconds);
}

void requireIncreasing(const std::string& file, const std::vector<Timestamp>& t,
                       const std::vector<long>& lines) {
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (t[i] <= t[i - 1]) {
      throw InputError(file, lines[i],
                       t[i] == t[i - 1] ? "duplicate timestamp"
                                        : "timestamps are not increasing");
    }
  }
}

std::size_t requireNonDecreasing(const std::string& file, const std::vector<Timestamp>& t,
                                 const std::vector<long>& lines) {
  std::size_t repeated = 0;
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (t[i] < t[i - 1]) throw InputError(file, lines[i], "timestamps are not increasing");
    if (t[i] == t[i - 1]) ++repeated;
  }
  return repeated;
}

}  // namespace hdvio::eval
