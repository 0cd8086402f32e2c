// The process-wide pool of task arenas (kernels/include/locus/kernels/parallel/task_arenas.hpp).
#include "locus/kernels/parallel/task_arenas.hpp"

#include <mutex>
#include <vector>

namespace locus::detail {

namespace {

class ArenaPool {
 public:
  std::unique_ptr<tbb::task_arena> take(int threads) {
    {
      std::lock_guard<std::mutex> lk(m_);
      if (static_cast<size_t>(threads) < idle_.size() && !idle_[threads].empty()) {
        std::unique_ptr<tbb::task_arena> a = std::move(idle_[threads].back());
        idle_[threads].pop_back();
        return a;
      }
    }
    return std::make_unique<tbb::task_arena>(threads);
  }
  void give(int threads, std::unique_ptr<tbb::task_arena> a) {
    std::lock_guard<std::mutex> lk(m_);
    if (idle_.size() <= static_cast<size_t>(threads)) idle_.resize(static_cast<size_t>(threads) + 1);
    idle_[threads].push_back(std::move(a));
  }

 private:
  std::mutex m_;
  std::vector<std::vector<std::unique_ptr<tbb::task_arena>>> idle_;  // by concurrency
};

// Never destroyed: a host thread still inside a call at exit returns its arena
// to a live pool. The idle arenas hold no threads; the OS reclaims the rest.
ArenaPool& pool() {
  static ArenaPool* p = new ArenaPool;
  return *p;
}

}  // namespace

BorrowedArena::BorrowedArena(int threads) : threads_(threads), arena_(pool().take(threads)) {}
BorrowedArena::~BorrowedArena() { pool().give(threads_, std::move(arena_)); }

}  // namespace locus::detail
