#pragma once
// Runs a shell command for the app tests: exit code and everything it printed (stdout and
// stderr together, in order).
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace hdvio::test {

struct CommandOutcome {
  int exit_code = -1;  // -1: not started or killed by a signal
  std::string output;
};

inline CommandOutcome runCommand(const std::string& command) {
  CommandOutcome o;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  std::array<char, 512> buf{};
  while (pipe && fgets(buf.data(), buf.size(), pipe)) o.output += buf.data();
  const int status = pipe ? pclose(pipe) : -1;
  o.exit_code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return o;
}

}  // namespace hdvio::test
