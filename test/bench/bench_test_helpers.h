#pragma once
// What the hdvio_bench app tests share: starting the tool, reading its files.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "../common/run_command.h"

namespace hdvio::test {

inline CommandOutcome runShell(const std::string& cmd) { return runCommand(cmd); }

inline CommandOutcome bench(const std::string& args) {
  return runShell(std::string(HDVIO_BENCH_BINARY) + " " + args);
}

// An empty folder of this process under the temp directory.
inline std::filesystem::path freshTempDir(const std::string& prefix) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / (prefix + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string readFile(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The number after `"key": ` at or after `from` in a JSON text (these tests' files only).
inline double jsonNumber(const std::string& json, const std::string& key, std::size_t from = 0) {
  const std::size_t at = json.find("\"" + key + "\": ", from);
  if (at == std::string::npos) return NAN;
  return std::strtod(json.c_str() + at + key.size() + 4, nullptr);
}

}  // namespace hdvio::test
