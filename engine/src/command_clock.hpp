// The wall-clock helpers of the engine's commands: seconds since a start and
// the median of a command's repeats (the reports give medians, robust to one
// slow run). Internal to the engine.
#pragma once
#include <algorithm>
#include <chrono>
#include <vector>

namespace locus::command_clock {

inline double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Mean of the two middle values for an even count; 0 for none.
inline double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

}  // namespace locus::command_clock
