// Single-thread streaming read bandwidth of this machine, for turning a
// query's byte count into a time floor (locus-bench logmap: the exact solves
// cannot finish faster than their factor bytes take to stream from memory).
// The buffer is much larger than the last-level cache, so each repeat reads
// from DRAM; eight independent accumulators keep the loop memory-bound rather
// than add-latency-bound.
#pragma once
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <vector>

namespace locus::bench {

struct StreamBandwidth {
  double best_bytes_per_s = 0, median_bytes_per_s = 0;
  double checksum = 0;  // keeps the reads observable
};

inline StreamBandwidth measure_stream_read(std::size_t bytes = std::size_t(512) << 20, int repeats = 7) {
  std::vector<double> buf(bytes / sizeof(double));
  for (std::size_t i = 0; i < buf.size(); ++i) buf[i] = static_cast<double>(i & 1023);  // touch every page
  std::vector<double> rates;
  StreamBandwidth out;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    double acc[8] = {};
    const std::size_t n8 = buf.size() / 8 * 8;
    for (std::size_t i = 0; i < n8; i += 8)
      for (int k = 0; k < 8; ++k) acc[k] += buf[i + k];
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (double a : acc) out.checksum += a;
    rates.push_back(static_cast<double>(n8 * sizeof(double)) / secs);
  }
  std::sort(rates.begin(), rates.end());
  out.best_bytes_per_s = rates.back();
  out.median_bytes_per_s = rates[rates.size() / 2];
  return out;
}

}  // namespace locus::bench
