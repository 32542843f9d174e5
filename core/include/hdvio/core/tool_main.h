#pragma once
// The one error policy of every command-line tool: bad input (InputError) prints
// "error: <file>:<line>: <problem>" and exits with code 2; any other exception prints its
// message and exits with 1. No exception escapes main.
#include <cstdio>
#include <exception>
#include <functional>

#include "hdvio/core/error.h"

namespace hdvio {

inline int runTool(const std::function<int()>& body) {
  try {
    return body();
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}

}  // namespace hdvio
