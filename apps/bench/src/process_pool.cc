#include "hdvio/bench/process_pool.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <fstream>
#include <map>

extern char** environ;

namespace hdvio::bench {

namespace {

struct Running {
  std::size_t index;
  std::chrono::steady_clock::time_point start;
};

pid_t spawn(const Command& c) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, c.log.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  std::vector<char*> argv;
  for (const auto& a : c.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return rc == 0 ? pid : -1;
}

}  // namespace

std::vector<CommandOutcome> runCommands(const std::vector<Command>& commands, int jobs,
                                        const CommandDone& done) {
  std::vector<CommandOutcome> outcomes(commands.size());
  std::map<pid_t, Running> running;
  std::size_t next = 0;
  if (jobs < 1) jobs = 1;
  while (next < commands.size() || !running.empty()) {
    while (next < commands.size() && static_cast<int>(running.size()) < jobs) {
      const pid_t pid = spawn(commands[next]);
      if (pid < 0) {
        std::ofstream(commands[next].log, std::ios::app)
            << "error: cannot start " << commands[next].argv[0] << "\n";
        outcomes[next].exit_code = -1;
        if (done) done(next, outcomes[next]);
      } else {
        running[pid] = {next, std::chrono::steady_clock::now()};
      }
      ++next;
    }
    if (running.empty()) continue;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) break;  // no children left (should not happen)
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    CommandOutcome& o = outcomes[it->second.index];
    o.exit_code = WIFEXITED(status) ? WEXITSTATUS(status)
                                    : (WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1);
    o.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - it->second.start)
                   .count();
    const std::size_t index = it->second.index;
    running.erase(it);
    if (done) done(index, o);
  }
  return outcomes;
}

std::string shellQuote(const std::string& word) {
  bool plain = !word.empty();
  for (char c : word)
    plain = plain && (std::isalnum(static_cast<unsigned char>(c)) || std::string("/._-=+:,@").find(c) != std::string::npos);
  if (plain) return word;
  std::string out = "'";
  for (char c : word) out += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string shellLine(const Command& c) {
  std::string line;
  for (const auto& a : c.argv) line += (line.empty() ? "" : " ") + shellQuote(a);
  if (!c.log.empty()) line += " > " + shellQuote(c.log) + " 2>&1";
  return line;
}

std::string lastErrorLine(const std::string& log_path) {
  std::ifstream in(log_path);
  std::string line, last_error, last;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    last = line;
    if (line.rfind("error:", 0) == 0) last_error = line;
  }
  return last_error.empty() ? last : last_error;
}

}  // namespace hdvio::bench
