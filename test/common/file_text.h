#pragma once
// A whole file as a string (binary), for byte-for-byte comparisons in tests.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace hdvio::test {

inline std::string readFile(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace hdvio::test
