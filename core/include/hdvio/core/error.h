#pragma once
// One error type for bad user input (files, configs, flags). Apps catch it, print it once and
// exit with code 2; nothing else in the library calls exit().
#include <stdexcept>
#include <string>

namespace hdvio {

constexpr int kExitBadInput = 2;

class InputError : public std::runtime_error {
 public:
  // file may be empty (e.g. a flag); line <= 0 means "no line".
  InputError(std::string file, long line, const std::string& problem)
      : std::runtime_error(format(file, line, problem)),
        file_(std::move(file)), line_(line), problem_(problem) {}
  const std::string& file() const { return file_; }
  long line() const { return line_; }
  const std::string& problem() const { return problem_; }

 private:
  static std::string format(const std::string& file, long line, const std::string& problem) {
    std::string s = file;
    if (line > 0) s += ":" + std::to_string(line);
    if (!s.empty()) s += ": ";
    return s + problem;
  }
  std::string file_;
  long line_;
  std::string problem_;
};

}  // namespace hdvio
