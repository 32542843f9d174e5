#pragma once
// The one command-line parser of every tool: gflags with a short `--help`.
//
// gflags' own --help lists every flag linked into the binary (~100 lines of glog and gflags
// internals). Here `--help` (or `-h`) prints the tool's usage text and only the flags defined in
// the tool's main file, on stdout, and exits 0. `--helpfull` and the other gflags help flags keep
// their gflags meaning. An unknown flag or a value of the wrong type is bad input: one line
// "error: --flag: ..." and exit code 2. Header-only so that hdvio_core need not link gflags.
//
//   int main(int argc, char** argv) {
//     hdvio::parseToolFlags(&argc, &argv, __FILE__,
//                           "usage: hdvio_x --in <file>\n"
//                           "what it does\n"
//                           "example: hdvio_x --in data.csv");
//     if (const int bad = hdvio::checkRequiredFlags(__FILE__, {FLAGS_in})) return bad;
//     ...
#include <gflags/gflags.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

#include "hdvio/core/error.h"

DECLARE_bool(help);
DECLARE_bool(helpfull);

namespace hdvio {
namespace detail {

inline std::string baseName(const std::string& path) {
  const std::size_t slash = path.find_last_of("/\\");
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// "--name=default" as the user would type it; strings are quoted so that an empty default shows.
inline std::string flagWithDefault(const gflags::CommandLineFlagInfo& f) {
  const std::string value = f.type == "string" ? "\"" + f.default_value + "\"" : f.default_value;
  return "--" + f.name + "=" + value;
}

// gflags answers an unknown flag or a bad value with its own message and exit code 1; here such
// flags are bad input like any other: one line "error: --flag: problem" and exit code 2.
inline void rejectBadFlags(int argc, char** argv, const char* tool) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") break;
    if (arg.size() < 2 || arg[0] != '-') continue;
    const std::string body = arg.substr(arg[1] == '-' ? 2 : 1);
    const std::size_t eq = body.find('=');
    std::string name = body.substr(0, eq);
    std::replace(name.begin(), name.end(), '-', '_');
    gflags::CommandLineFlagInfo info;
    const bool known = gflags::GetCommandLineFlagInfo(name.c_str(), &info);
    const bool negated = !known && name.rfind("no", 0) == 0 &&
                         gflags::GetCommandLineFlagInfo(name.substr(2).c_str(), &info) && info.type == "bool";
    auto fail = [&](const std::string& problem) {
      std::fprintf(stderr, "error: --%s: %s (%s --help lists the flags)\n", name.c_str(), problem.c_str(), tool);
      std::exit(2);
    };
    if (!known && !negated) fail("unknown flag");
    if (negated || baseName(info.filename).find("gflags") != std::string::npos) continue;
    std::string value;
    if (eq != std::string::npos) value = body.substr(eq + 1);
    else if (info.type == "bool") continue;
    else if (i + 1 < argc) value = argv[++i];
    else fail("needs a value");
    // Sets the flag as the parser will; an empty answer means the value does not parse.
    if (gflags::SetCommandLineOption(name.c_str(), value.c_str()).empty())
      fail("'" + value + "' is not a valid " + info.type);
  }
}

}  // namespace detail

// The flags defined in `source_file` (the tool's main file, __FILE__), sorted by name.
inline std::vector<gflags::CommandLineFlagInfo> toolFlags(const char* source_file) {
  std::vector<gflags::CommandLineFlagInfo> all, own;
  gflags::GetAllFlags(&all);
  const std::string base = detail::baseName(source_file);
  for (const auto& f : all)
    if (detail::baseName(f.filename) == base) own.push_back(f);
  std::sort(own.begin(), own.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return own;
}

// The text `--help` prints: the usage message, the tool's flags one per line, a pointer to
// --helpfull.
inline std::string toolHelp(const char* source_file) {
  std::string text = gflags::ProgramUsage();
  if (!text.empty() && text.back() != '\n') text += '\n';
  const auto flags = toolFlags(source_file);
  if (!flags.empty()) {
    // Descriptions aligned in one column; a flag with a long default (a path) just overhangs it.
    constexpr std::size_t kMaxColumn = 28;
    std::size_t width = 0;
    for (const auto& f : flags) width = std::max(width, detail::flagWithDefault(f).size());
    width = std::min(width, kMaxColumn);
    text += "flags:\n";
    for (const auto& f : flags) {
      const std::string head = detail::flagWithDefault(f);
      text += "  " + head + std::string(head.size() < width ? width - head.size() + 2 : 2, ' ') +
              f.description + "\n";
    }
  }
  text += "--helpfull lists all flags, including those of glog and gflags.\n";
  return text;
}

// Parses argv like gflags::ParseCommandLineFlags(argc, argv, true), answering --help / -h itself.
inline void parseToolFlags(int* argc, char*** argv, const char* source_file, const char* usage) {
  gflags::SetUsageMessage(usage);
  for (int i = 1; i < *argc; ++i) {
    if (std::strcmp((*argv)[i], "--") == 0) break;
    if (std::strcmp((*argv)[i], "-h") == 0) (*argv)[i] = const_cast<char*>("--help");
  }
  detail::rejectBadFlags(*argc, *argv, detail::baseName((*argv)[0]).c_str());
  gflags::ParseCommandLineNonHelpFlags(argc, argv, true);
  if (FLAGS_help) {
    std::fputs(toolHelp(source_file).c_str(), stdout);
    std::exit(0);
  }
  if (FLAGS_helpfull) {  // gflags' own listing, but asking for help is not an error (gflags: 1)
    gflags::ShowUsageWithFlags((*argv)[0]);
    std::exit(0);
  }
  gflags::HandleCommandLineHelpFlags();
}

// A tool called without its required input: 0 when none of the string flags `required` is empty
// and `also_ok` holds (e.g. the count of positional arguments, argc == 2); otherwise the tool's
// help goes to stderr, then `problem` as one line "error: <problem>" if given, and the answer is
// the exit code kExitBadInput for main to return.
inline int checkRequiredFlags(const char* source_file,
                              std::initializer_list<std::reference_wrapper<const std::string>> required,
                              bool also_ok = true, const char* problem = nullptr) {
  bool ok = also_ok;
  for (const std::string& flag : required) ok = ok && !flag.empty();
  if (ok) return 0;
  std::fputs(toolHelp(source_file).c_str(), stderr);
  if (problem) std::fprintf(stderr, "error: %s\n", problem);
  return kExitBadInput;
}

}  // namespace hdvio
