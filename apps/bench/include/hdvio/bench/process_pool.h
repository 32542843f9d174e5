#pragma once
// Runs external commands (hdvio_sim, hdvio_run) as separate processes, at most `jobs` at a time,
// each with its stdout and stderr in a log file. A failing command is an outcome, not an error:
// the benchmark reports it and carries on.
#include <functional>
#include <string>
#include <vector>

namespace hdvio::bench {

struct Command {
  std::string label;              // for progress lines
  std::vector<std::string> argv;  // argv[0] is the program path
  std::string log;                // stdout + stderr go here (truncated first)
};

struct CommandOutcome {
  int exit_code = -1;  // -1: could not start, 128 + n: killed by signal n
  double wall_s = 0.0;
};

// Called in the parent as each command ends (in completion order).
using CommandDone = std::function<void(std::size_t index, const CommandOutcome&)>;

std::vector<CommandOutcome> runCommands(const std::vector<Command>& commands, int jobs,
                                        const CommandDone& done = nullptr);

// The command as one POSIX shell line with its log redirection (for --emit-jobs).
std::string shellLine(const Command& command);
std::string shellQuote(const std::string& word);

// The last line of a log that starts with "error:", else its last non-empty line.
std::string lastErrorLine(const std::string& log_path);

}  // namespace hdvio::bench
