#pragma once
// CPU time of the calling thread, s: the per-frame / per-update cost on one core, whatever else
// runs on the machine (wall time also counts other processes). Reading it is a system call
// (~1.4 us on the benchmark VM, more than an IMU step), so callers read it around whole frames,
// runs and updates, never per IMU step. Timing only: nothing an estimate depends on may read it.
#include <ctime>

namespace hdvio {

inline double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace hdvio
