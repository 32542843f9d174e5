#pragma once
// For tests that a reader does not allocate what a corrupt file declares: run the reader in a
// child (EXPECT_EXIT) whose address space may grow only by `extra_bytes`, so a large
// allocation throws std::bad_alloc instead of passing unnoticed on a big machine.
#include <sys/resource.h>
#include <unistd.h>

#include <cstddef>
#include <fstream>

namespace hdvio::test {

inline void limitAddressSpaceGrowth(std::size_t extra_bytes) {
  std::ifstream statm("/proc/self/statm");
  long pages = 0;
  statm >> pages;
  const rlim_t limit = static_cast<rlim_t>(pages) * sysconf(_SC_PAGESIZE) + extra_bytes;
  const rlimit rl{limit, limit};
  setrlimit(RLIMIT_AS, &rl);
}

}  // namespace hdvio::test
