// The host's allocator (core/include/locus/core/host_allocator.hpp).
#include "locus/core/host_allocator.hpp"
#include "locus/core/release_free_memory.hpp"

#include <atomic>
#include <cstdint>
#include <cstdlib>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace locus {

namespace {

struct Hooks {
  HostAllocFn alloc;
  HostFreeFn free;
  void* user;
  const Hooks* next;  // the one set before (g_all_hooks)
};

// The header in front of every block: 32 bytes keep the block 16-byte aligned.
struct alignas(16) Header {
  uint64_t magic;
  const Hooks* hooks;  // nullptr: the C library's malloc
  std::size_t bytes;
  uint64_t reserved;
};
static_assert(sizeof(Header) == 32);
constexpr uint64_t kMagic = 0x6c6f637573616c6cull;  // "locusall"

// Every Hooks ever set stays allocated (a few bytes per locus_set_allocator
// call): a block's header may point at it long after the host switched.
std::atomic<const Hooks*> g_hooks{nullptr};
// All of them, newest first: kept reachable (and so not reported as leaks) for
// as long as a block may name them, i.e. for the process' life.
std::atomic<const Hooks*> g_all_hooks{nullptr};

}  // namespace

void set_host_allocator(HostAllocFn alloc, HostFreeFn free, void* user) noexcept {
  Hooks* h = nullptr;
  if (alloc && free) {
    h = new (std::nothrow) Hooks{alloc, free, user, nullptr};
    if (h) {
      const Hooks* head = g_all_hooks.load(std::memory_order_relaxed);
      do {
        h->next = head;
      } while (!g_all_hooks.compare_exchange_weak(head, h, std::memory_order_release, std::memory_order_relaxed));
    }
  }
  g_hooks.store(h, std::memory_order_release);
}

void* host_allocate_nothrow(std::size_t bytes) noexcept {
  if (bytes > static_cast<std::size_t>(-1) - sizeof(Header)) return nullptr;
  const Hooks* h = g_hooks.load(std::memory_order_acquire);
  const std::size_t total = sizeof(Header) + bytes;
  void* raw = nullptr;
  if (h) {
    try {
      raw = h->alloc(total, h->user);
    } catch (...) {  // a C++ host callback that throws: no memory
      raw = nullptr;
    }
  } else {
    raw = std::malloc(total);
  }
  if (!raw) return nullptr;
  Header* hd = static_cast<Header*>(raw);
  *hd = Header{kMagic, h, bytes, 0};
  return hd + 1;
}

void* host_allocate(std::size_t bytes) {
  void* p = host_allocate_nothrow(bytes);
  if (!p) throw std::bad_alloc();
  return p;
}

void host_deallocate(void* p) noexcept {
  if (!p) return;
  Header* hd = static_cast<Header*>(p) - 1;
  if (hd->magic != kMagic) {  // not ours (e.g. a C library block METIS frees)
    std::free(p);
    return;
  }
  hd->magic = 0;  // a second free of the same block then goes to free(), which reports it
  const Hooks* h = hd->hooks;
  if (h)
    h->free(hd, h->user);
  else
    std::free(hd);
}

void release_free_memory() noexcept {
#if defined(__GLIBC__)
  if (!g_hooks.load(std::memory_order_acquire)) malloc_trim(0);
#endif
}

std::size_t host_allocation_size(const void* p) noexcept {
  if (!p) return 0;
  const Header* hd = static_cast<const Header*>(p) - 1;
  return hd->magic == kMagic ? hd->bytes : 0;
}

}  // namespace locus
