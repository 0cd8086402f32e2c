// Wall-clock lap timer for phase timings (seconds), beside thread_cpu_time.hpp.
#pragma once
#include <chrono>

namespace locus {

// Each lap() returns the seconds since construction or the previous lap().
class BatchStopwatch {
 public:
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - start_).count();
    start_ = now;
    return s;
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace locus
