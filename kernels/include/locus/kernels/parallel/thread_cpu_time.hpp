// CPU time of the calling thread, for phase timings that other processes on a
// loaded machine do not inflate (benchmarks, per-phase query statistics).
#pragma once
#include <ctime>

namespace locus {

inline double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace locus
