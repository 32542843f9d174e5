#pragma once
// The one error policy of every command-line tool: bad input (InputError) prints
// "error: <file>:<line>: <problem>" and exits with code 2; any other exception prints its
// message and exits with 1 (ToolErrorPolicy: std::invalid_argument as bad input, a prefix for
// the rest). No exception escapes main. A required flag left empty is answered before, with
// the tool's help (checkRequiredFlags in tool_flags.h).
//
//   int main(int argc, char** argv) {
//     hdvio::parseToolFlags(&argc, &argv, __FILE__, "usage: ...");   // tool_flags.h
//     if (const int bad = hdvio::checkRequiredFlags(__FILE__, {FLAGS_in})) return bad;
//     return hdvio::runTool(run);
//   }
#include <cstdio>
#include <exception>
#include <functional>
#include <stdexcept>

#include "hdvio/core/error.h"

namespace hdvio {

// What a tool's body may need beyond the default policy.
struct ToolErrorPolicy {
  // std::invalid_argument (a library's check of a value the user gave) is bad input too: exit 2.
  bool invalid_argument_is_bad_input = false;
  // Put before the message of any other exception (exit 1), e.g. "training failed: ".
  const char* failure_prefix = "";
};

namespace detail {
// One line on stderr, after whatever the tool already printed on stdout (as std::cerr would).
inline int toolError(int code, const char* prefix, const char* what) {
  std::fflush(stdout);
  std::fprintf(stderr, "error: %s%s\n", prefix, what);
  return code;
}
}  // namespace detail

// Runs the tool's body and answers every exception with one line on stderr and the exit code.
inline int runTool(const std::function<int()>& body, const ToolErrorPolicy& policy = {}) {
  try {
    return body();
  } catch (const InputError& e) {
    return detail::toolError(kExitBadInput, "", e.what());
  } catch (const std::invalid_argument& e) {
    if (policy.invalid_argument_is_bad_input) return detail::toolError(kExitBadInput, "", e.what());
    return detail::toolError(1, policy.failure_prefix, e.what());
  } catch (const std::exception& e) {
    return detail::toolError(1, policy.failure_prefix, e.what());
  }
}

}  // namespace hdvio
