// A host allocator that counts: every block it hands
// out is recorded; a free of a block it did not hand out is counted as foreign
// (and not freed: it would corrupt the C library's heap if it were not malloc's).
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <unordered_map>

namespace locus::test {

struct CountingAllocator {
  std::mutex mu;
  std::unordered_map<void*, size_t> live;
  int64_t allocs = 0, frees = 0, foreign_frees = 0, refused = 0;
  int64_t bytes = 0, max_block = 0;
  int64_t fail_after = -1;  // >= 0: refuse every allocation after this many
  // With cancel_flag: raised once this many allocations were made (a host's
  // cancel arriving in the middle of a call).
  int64_t cancel_after = -1;
  std::atomic<bool>* cancel_flag = nullptr;

  static void* alloc(size_t size, void* user) {
    auto& c = *static_cast<CountingAllocator*>(user);
    std::lock_guard<std::mutex> lock(c.mu);
    if (c.fail_after >= 0 && c.allocs >= c.fail_after) {
      ++c.refused;
      return nullptr;
    }
    void* p = std::malloc(size);
    if (!p) return nullptr;
    ++c.allocs;
    c.bytes += static_cast<int64_t>(size);
    c.max_block = std::max<int64_t>(c.max_block, static_cast<int64_t>(size));
    c.live.emplace(p, size);
    if (c.cancel_flag && c.allocs == c.cancel_after) c.cancel_flag->store(true);
    return p;
  }
  static void free(void* p, void* user) {
    auto& c = *static_cast<CountingAllocator*>(user);
    std::lock_guard<std::mutex> lock(c.mu);
    auto it = c.live.find(p);
    if (it == c.live.end()) {
      ++c.foreign_frees;
      return;
    }
    c.live.erase(it);
    ++c.frees;
    std::free(p);
  }
  size_t live_blocks() {
    std::lock_guard<std::mutex> lock(mu);
    return live.size();
  }
};

}  // namespace locus::test
